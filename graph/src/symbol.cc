#include "quiver/graph/symbol.h"

#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

#include "quiver/hash.h"

namespace quiver::graph {
namespace {

// Chunked, append-only storage: readers index without a lock because chunks never move and a
// string is fully constructed before its index is published.
class Interner {
 public:
  static constexpr std::uint32_t kChunkBits = 12;
  static constexpr std::uint32_t kChunkSize = 1u << kChunkBits;
  static constexpr std::uint32_t kMaxChunks = 4096;

  Interner() { intern(""); }

  std::uint32_t intern(std::string_view s) {
    std::lock_guard<std::mutex> lock(mu_);
    auto it = index_.find(std::string(s));
    if (it != index_.end()) return it->second;
    std::uint32_t id = size_.load(std::memory_order_relaxed);
    std::uint32_t chunk = id >> kChunkBits;
    if (chunk >= kMaxChunks) std::abort();  // 16M distinct names: a runaway caller
    if (!chunks_[chunk]) chunks_[chunk] = std::make_unique<std::array<Slot, kChunkSize>>();
    Slot& slot = (*chunks_[chunk])[id & (kChunkSize - 1)];
    slot.text = std::string(s);
    slot.hash = mix64(fnv1a64(s));
    index_.emplace(std::string(s), id);
    size_.store(id + 1, std::memory_order_release);
    return id;
  }
  const std::string& str(std::uint32_t id) const {
    static const std::string kBad = "<bad-symbol>";
    if (id >= size_.load(std::memory_order_acquire)) return kBad;
    return (*chunks_[id >> kChunkBits])[id & (kChunkSize - 1)].text;
  }
  std::uint64_t hash(std::uint32_t id) const {
    if (id >= size_.load(std::memory_order_acquire)) return 0;
    return (*chunks_[id >> kChunkBits])[id & (kChunkSize - 1)].hash;
  }

 private:
  std::mutex mu_;
  std::unordered_map<std::string, std::uint32_t> index_;
  struct Slot {
    std::string text;
    std::uint64_t hash = 0;
  };
  std::array<std::unique_ptr<std::array<Slot, kChunkSize>>, kMaxChunks> chunks_;
  std::atomic<std::uint32_t> size_{0};
};

Interner& interner() {
  static Interner* table = new Interner();  // never destroyed: symbols outlive static dtors
  return *table;
}

}  // namespace

Symbol::Symbol(std::string_view name) : index_(name.empty() ? 0 : interner().intern(name)) {}

const std::string& Symbol::str() const { return interner().str(index_); }
std::uint64_t Symbol::stable_hash() const { return interner().hash(index_); }

namespace symbols {
Symbol rt() {
  static const Symbol s("RT");
  return s;
}
Symbol pose() {
  static const Symbol s("pose");
  return s;
}
}  // namespace symbols

}  // namespace quiver::graph
