// One thread that runs jobs in order and owns whatever GL context it makes current.
//
// A GL context is current on one thread at a time, and inside ParaView an EGL context made
// current on ParaView's own thread clashes with its GLX context (EGL_BAD_ACCESS, occasional
// aborts). So every GL call of a GPU simulation runs on a GlThread, the one of the process's
// shared context (shared_gl_context.h): the caller posts a job and waits for it; exceptions
// thrown by a job come back to the caller.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>

namespace softbody::gpu
{

class GlThread
{
public:
  GlThread();
  /// Finishes the queued jobs, then joins the thread.
  ~GlThread();
  GlThread(const GlThread&) = delete;
  GlThread& operator=(const GlThread&) = delete;

  /// Runs `job` on the GL thread and returns its result (or rethrows its exception).
  template <typename Job>
  auto run(Job&& job) -> std::invoke_result_t<Job>
  {
    using Result = std::invoke_result_t<Job>;
    auto task = std::make_shared<std::packaged_task<Result()>>(std::forward<Job>(job));
    std::future<Result> result = task->get_future();
    post([task] { (*task)(); });
    return result.get();
  }

  /// True on the GL thread itself (for assertions).
  bool isCurrentThread() const { return std::this_thread::get_id() == Thread.get_id(); }

private:
  void post(std::function<void()> job);
  void loop();

  std::mutex Mutex;
  std::condition_variable JobsChanged;
  std::deque<std::function<void()>> Jobs;
  bool Stopping = false;
  std::thread Thread; // last: starts after the members above exist
};

} // namespace softbody::gpu
