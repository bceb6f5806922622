#pragma once
/// @file
/// Where an engine's thread is in user code: since when, in which callback, of which action. The
/// engine marks every call into an agent's code (a Scope around it); a watcher on another thread
/// (LivenessKeeper) reads it to keep the agent alive for its peers while the code blocks, and to
/// report a callback that does not return.
///
/// Threading: enter() and the Scope belong to the engine's thread; snapshot() may be called from
/// any thread (a seqlock: the engine never waits for a reader).

#include <atomic>
#include <cstdint>
#include <string>

namespace quiver::agents::inline runtime {

class CallbackWatch {
 public:
  /// @param agent the agent's name, for reports. Engine thread.
  explicit CallbackWatch(std::string agent) : agent_(std::move(agent)) {}
  CallbackWatch(const CallbackWatch&) = delete;
  CallbackWatch& operator=(const CallbackWatch&) = delete;

  /// Marks one call into user code until it goes out of scope. Nested scopes (user code that
  /// calls back into the engine, which calls user code again) count as the outermost one.
  class Scope {
   public:
    /// Takes over `o`'s mark (`o` then marks nothing). Engine thread only.
    Scope(Scope&& o) noexcept : w_(o.w_) { o.w_ = nullptr; }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;
    /// Ends the mark (the outermost scope ends the call). Engine thread only.
    /// @pre Scopes end in the reverse order they began (as locals do).
    ~Scope() {
      if (w_ != nullptr) w_->leave();
    }

   private:
    friend class CallbackWatch;
    explicit Scope(CallbackWatch* w) : w_(w) {}
    CallbackWatch* w_;
  };

  /// Engine thread: user code starts now (`now_ns` on the clock the watcher compares with).
  /// `callback` is a static string ("process()", "a timer", ...); `action` (may be null) must
  /// outlive the scope.
  /// @returns the scope marking the call (nested: only the outermost one is recorded).
  [[nodiscard]] Scope enter(const char* callback, const std::string* action, std::int64_t now_ns);

  /// What the engine's thread is doing, read from any thread.
  struct Snapshot {
    bool busy = false;           ///< in user code
    std::int64_t since_ns = 0;   ///< since when (the engine's clock)
    std::uint64_t call = 0;      ///< which call (each outermost scope has its own number)
    const char* callback = "";   ///< e.g. "process()"
    std::string action;          ///< the action's name, or ""
  };
  /// @returns a consistent snapshot (retried while the engine writes).
  /// Thread-safe; never blocks the engine (it spins only while the engine writes a few fields).
  Snapshot snapshot() const;
  /// @returns the agent's name. Any thread, once set_agent() is no longer called.
  const std::string& agent() const { return agent_; }
  /// Engine thread, before a watcher starts: the agent's name.
  void set_agent(std::string agent) { agent_ = std::move(agent); }

 private:
  void leave();

  std::string agent_;
  int depth_ = 0;  // engine thread only
  std::atomic<std::uint64_t> seq_{0};  // odd while the engine writes the fields below
  std::atomic<std::int64_t> since_{0};
  std::atomic<std::uint64_t> call_{0};
  std::atomic<bool> busy_{false};
  std::atomic<const char*> callback_{""};
  std::atomic<const std::string*> action_{nullptr};
};

}  // namespace quiver::agents::inline runtime
