#pragma once
/// @file
/// Long work off an agent's thread (speech synthesis, planning, a camera frame): run(work, done)
/// runs `work` on the runner's worker thread, where it must not touch the graph, then hands
/// `done` back to the agent's thread (through the engine's post()), where it may. The agent's
/// loop, its liveness and its locks never wait for a job.
///
/// In the simulator jobs run inline (work at once, done at the next round), so that a seed
/// replays exactly.
///
/// Threading: run() from the agent's thread; work() on the worker thread; done() on the agent's.

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

namespace quiver::agents::inline runtime {

class JobRunner {
 public:
  enum class Mode : std::uint8_t {
    kThread,  ///< a worker thread, started with the first job
    kInline,  ///< work runs in run() itself (deterministic hosts)
  };
  /// `post_back` hands a function to the agent's thread (the engine's post()).
  /// @pre `post_back` is set and thread-safe (kThread calls it from the worker thread).
  JobRunner(Mode mode, std::function<void(std::function<void()>)> post_back);
  /// Waits for the job in progress, drops those not started (their done() never runs).
  /// The job in progress still posts its done() through `post_back`. Agent's thread.
  /// @pre Not called from a job's work().
  ~JobRunner();
  JobRunner(const JobRunner&) = delete;
  JobRunner& operator=(const JobRunner&) = delete;

  /// Queues `work`; when it returns, `done` (may be empty) is posted to the agent's thread. Jobs
  /// run one at a time, in order. An exception from `work` is caught and reported to `done`'s
  /// caller as a log line through `on_error` (if set).
  /// `done` is posted even when `work` threw. kInline: `work` runs (and `done` is posted) before
  /// run() returns. Agent's thread.
  void run(std::function<void()> work, std::function<void()> done);
  /// Receives a line for each job whose work threw; it runs on the worker thread (kInline: in
  /// run()), so it must be thread-safe. @pre Set before the first run().
  void on_error(std::function<void(const std::string&)> cb) { on_error_ = std::move(cb); }

 private:
  struct Job {
    std::function<void()> work, done;
  };
  void loop();
  void execute(Job& j);

  Mode mode_;
  std::function<void(std::function<void()>)> post_back_;
  std::function<void(const std::string&)> on_error_;
  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<Job> queue_;  // guarded by mu_
  bool stopping_ = false;  // guarded by mu_
  std::thread worker_;
};

}  // namespace quiver::agents::inline runtime
