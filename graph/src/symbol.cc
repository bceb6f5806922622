// Interned strings for attribute names and node and edge types: a process-wide table that readers index without
// a lock.
#include "quiver/graph/symbol.h"

#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "quiver/graph/limits.h"
#include "quiver/base/hash.h"

namespace quiver::graph {
namespace {

// Chunked, append-only storage: readers index without a lock because chunks never move and a
// string is fully constructed before its index is published. The name -> index map is read under
// a shared lock, so a lookup allocates nothing and readers never wait for
// each other; only a new name takes the exclusive lock.
class Interner {
 public:
  static constexpr std::uint32_t kChunkBits = 12;
  static constexpr std::uint32_t kChunkSize = 1u << kChunkBits;
  static constexpr std::uint32_t kMaxChunks = (limits::kMaxSymbols + 1 + kChunkSize - 1) / kChunkSize;

  Interner() { (void)add_locked(""); }

  std::uint32_t find(std::string_view s) const {
    std::shared_lock<std::shared_mutex> lock(mu_);
    auto it = index_.find(s);
    return it == index_.end() ? 0 : it->second;
  }

  Result<std::uint32_t> intern(std::string_view s) {
    if (std::uint32_t id = find(s)) return id;
    std::unique_lock<std::shared_mutex> lock(mu_);
    auto it = index_.find(s);
    if (it != index_.end()) return it->second;
    return add_locked(s);
  }

  std::size_t count() const { return size_.load(std::memory_order_acquire) - 1; }

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
  Result<std::uint32_t> add_locked(std::string_view s) {
    std::uint32_t id = size_.load(std::memory_order_relaxed);
    if (id > limits::kMaxSymbols || text_bytes_ + s.size() > limits::kMaxSymbolBytes)
      return make_error(ErrorCode::kTooLarge,
                        "the table of names is full (" + std::to_string(id - 1) + " names, " +
                            std::to_string(text_bytes_) + " bytes; limits " + std::to_string(limits::kMaxSymbols) +
                            " and " + std::to_string(limits::kMaxSymbolBytes) + "): cannot add " + quote_name(s));
    std::uint32_t chunk = id >> kChunkBits;
    if (!chunks_[chunk]) chunks_[chunk] = std::make_unique<std::array<Slot, kChunkSize>>();
    Slot& slot = (*chunks_[chunk])[id & (kChunkSize - 1)];
    slot.text = std::string(s);
    slot.hash = mix64(fnv1a64(s));
    text_bytes_ += s.size();
    index_.emplace(std::string_view(slot.text), id);
    size_.store(id + 1, std::memory_order_release);
    return id;
  }

  struct ViewHash {
    std::size_t operator()(std::string_view s) const { return fnv1a64(s); }
  };
  struct Slot {
    std::string text;
    std::uint64_t hash = 0;
  };

  mutable std::shared_mutex mu_;
  // Keys view the slots' text, which never moves: no second copy of every name.
  std::unordered_map<std::string_view, std::uint32_t, ViewHash> index_;
  std::array<std::unique_ptr<std::array<Slot, kChunkSize>>, kMaxChunks> chunks_;
  std::atomic<std::uint32_t> size_{0};
  std::uint64_t text_bytes_ = 0;
};

Interner& interner() {
  static Interner* table = new Interner();  // never destroyed: symbols outlive static dtors
  return *table;
}

// Each thread's last names looked up, by hash: code names its attributes and types by string
// ("count", "in"), so most lookups are of a few names again and again, and a hit here costs a hash
// and one comparison instead of the shared lock and the table (a third of a simulated Barthel run
// went to those). An entry is checked against the interned text, which never changes, so a stale or
// colliding entry is only a miss.
struct Recent {
  std::uint64_t hash = 0;
  std::uint32_t id = 0;  // 0: empty
};
constexpr std::size_t kRecent = 256;

Recent& recent_slot(std::uint64_t hash) {
  thread_local std::array<Recent, kRecent> recent{};
  return recent[hash % kRecent];
}

std::uint32_t recent_id(std::string_view name, std::uint64_t hash) {
  const Recent& r = recent_slot(hash);
  return r.id != 0 && r.hash == hash && interner().str(r.id) == name ? r.id : 0;
}

Result<std::uint32_t> intern(std::string_view name) {
  const std::uint64_t hash = fnv1a64(name);
  if (std::uint32_t id = recent_id(name, hash)) return id;
  auto id = interner().intern(name);
  if (id.ok()) recent_slot(hash) = Recent{hash, *id};
  return id;
}

}  // namespace

Symbol::Symbol(std::string_view name) {
  if (name.empty()) return;
  auto id = intern(name);
  if (!id.ok()) throw std::length_error("Symbol(): " + id.error().message);
  index_ = *id;
}

Result<Symbol> Symbol::make(std::string_view name) {
  if (name.empty()) return Symbol();
  auto id = intern(name);
  if (!id.ok()) return id.error();
  return from_index(*id);
}

Symbol Symbol::find(std::string_view name) {
  if (name.empty()) return Symbol();
  const std::uint64_t hash = fnv1a64(name);
  if (std::uint32_t id = recent_id(name, hash)) return from_index(id);
  const std::uint32_t id = interner().find(name);
  if (id != 0) recent_slot(hash) = Recent{hash, id};
  return from_index(id);
}

std::size_t Symbol::interned_count() { return interner().count(); }

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
