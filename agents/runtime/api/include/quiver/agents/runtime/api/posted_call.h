#pragma once
/// @file
/// A call handed to another thread as a task: the caller gets a future of the result (or of the
/// exception the call threw). A task dropped before it ran leaves the future with
/// std::future_error (broken_promise).
#include <functional>
#include <future>
#include <memory>
#include <type_traits>
#include <utility>

namespace quiver::agents::inline runtime {

/// Wraps `fn` in a task, gives the task to `post` (which queues it for the thread that will run
/// it) and returns the future of its result.
/// Thread-safe if `post` is. @pre `post` takes a std::function<void()> and runs it at most once.
/// @returns the future of fn()'s result; fn's exception is stored in it, not thrown here.
template <class Post, class F>
auto posted_call(Post&& post, F fn) -> std::future<std::invoke_result_t<F&>> {
  using R = std::invoke_result_t<F&>;
  auto task = std::make_shared<std::packaged_task<R()>>(std::move(fn));
  std::future<R> result = task->get_future();
  std::forward<Post>(post)(std::function<void()>([task] { (*task)(); }));
  return result;
}

}  // namespace quiver
