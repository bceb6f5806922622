// Long work off an agent's thread: one worker, jobs in order, completions posted back.
#include "quiver/agents/runtime/engine/job_runner.h"

#include <exception>
#include <string>

namespace quiver::agents::inline runtime {

JobRunner::JobRunner(Mode mode, std::function<void(std::function<void()>)> post_back)
    : mode_(mode), post_back_(std::move(post_back)) {}

JobRunner::~JobRunner() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stopping_ = true;
    queue_.clear();
  }
  cv_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void JobRunner::execute(Job& j) {
  try {
    j.work();
  } catch (const std::exception& e) {
    if (on_error_) on_error_(std::string("a job threw: ") + e.what());
  } catch (...) {
    if (on_error_) on_error_("a job threw");
  }
  if (j.done) post_back_(std::move(j.done));
}

void JobRunner::run(std::function<void()> work, std::function<void()> done) {
  Job j{std::move(work), std::move(done)};
  if (mode_ == Mode::kInline) return execute(j);
  {
    std::lock_guard<std::mutex> lock(mu_);
    queue_.push_back(std::move(j));
    if (!worker_.joinable()) worker_ = std::thread([this] { loop(); });
  }
  cv_.notify_one();
}

void JobRunner::loop() {
  std::unique_lock<std::mutex> lock(mu_);
  for (;;) {
    cv_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (stopping_) return;
    Job j = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    execute(j);
    lock.lock();
  }
}

}  // namespace quiver::agents::inline runtime
