#include "gl_thread.h"

namespace softbody::gpu
{

GlThread::GlThread()
  : Thread([this] { loop(); })
{
}

GlThread::~GlThread()
{
  {
    std::lock_guard<std::mutex> lock(Mutex);
    Stopping = true;
  }
  JobsChanged.notify_one();
  Thread.join();
}

void GlThread::post(std::function<void()> job)
{
  {
    std::lock_guard<std::mutex> lock(Mutex);
    Jobs.push_back(std::move(job));
  }
  JobsChanged.notify_one();
}

void GlThread::loop()
{
  for (;;)
  {
    std::function<void()> job;
    {
      std::unique_lock<std::mutex> lock(Mutex);
      JobsChanged.wait(lock, [this] { return Stopping || !Jobs.empty(); });
      if (Jobs.empty())
      {
        return; // stopping, and nothing left to do
      }
      job = std::move(Jobs.front());
      Jobs.pop_front();
    }
    job(); // a packaged_task: exceptions are stored for the caller, never escape here
  }
}

} // namespace softbody::gpu
