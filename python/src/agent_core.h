#pragma once
// The C++ side of quiver.Agent: one DDS replica and its engine (the agent engine: timers, posted
// tasks, locks, the grammar guard) driven by its own thread. Everything that touches the replica
// (graph reads and writes, locks, the grammar guard, the frame tree, Python callbacks) runs on
// that thread; other threads hand it work through post(). A keeper thread keeps the agent alive
// for its peers while a Python callback blocks, and reports one that does not return.

#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "common.h"
#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/rules/grammar/grammar_guard.h"
#include "quiver/agents/rules/locks/locks.h"
#include "quiver/kinematics/frames.h"

namespace quiver::python {

struct AgentOptions {
  agents::DdsReplicaOptions replica;
  std::string grammar_file;
  std::string grammar_text;
  bool locks = true;
  agents::LockOptions lock_options;
  bool frames = true;
  /// On stop: replicate up to this long until every live agent peer holds all this replica holds.
  std::int64_t hand_over_ns = 2'000'000'000;
  /// A callback running longer is reported as hung on stderr (0: never).
  std::int64_t hang_ns = 1'000'000'000;
};

class AgentCore : public std::enable_shared_from_this<AgentCore> {
 public:
  /// Starts the thread and waits until the replica exists (call without the GIL).
  /// @returns the error that prevented the start.
  static Result<std::shared_ptr<AgentCore>> start(AgentOptions options);
  ~AgentCore();

  /// Stops the thread and waits for it (call without the GIL, not from the agent's thread).
  void stop();
  bool running() const { return running_.load(); }
  bool on_thread() const { return std::this_thread::get_id() == thread_id_; }

  /// Runs `fn` on the agent's thread. False if the agent has stopped (then `fn` is dropped).
  bool post_quietly(std::function<void()> fn);

  // Owner thread only:
  agents::DdsReplica& replica() { return *replica_; }
  agents::LockManager* locks() { return replica_->engine().lock_manager(); }
  agents::GrammarGuard* guard() { return replica_->engine().guard(); }
  kinematics::FrameTree* frames() { return frames_.get(); }
  const AgentOptions& options() const { return opt_; }

  /// With the GIL: keeps the first error a callback raised / hands it over (or null).
  void keep_error(py::error_already_set& e);
  py::object take_error();

 private:
  explicit AgentCore(AgentOptions o) : opt_(std::move(o)) {}
  void loop();
  void wake_to_stop();  // sets stop_ and ends the replica's round at once

  AgentOptions opt_;
  std::thread thread_;
  std::thread::id thread_id_;
  std::atomic<bool> running_{false};
  std::atomic<bool> stop_{false};
  std::unique_ptr<agents::DdsReplica> replica_;
  std::unique_ptr<kinematics::FrameTree> frames_;

  std::mutex mu_;  // guards the fields below and replica_'s lifetime against post_quietly()
  std::condition_variable cv_;
  bool started_ = false;
  std::optional<Error> start_error_;
  PyObject* first_error_ = nullptr;  // an exception instance (GIL)
};

}  // namespace quiver::python
