#include "shared_gl_context.h"

#include "egl_context.h"

#include "softbody/gpu/gpu_errors.h"

#include <cstdlib>
#include <mutex>

namespace softbody::gpu
{
namespace
{

/// Who is alive, for acquire() and the exit handler. Allocated once and never destroyed, on
/// purpose: simulations may be destroyed by static destructors after this file's statics
/// would have been, and must still find a valid mutex.
struct Registry
{
  std::mutex Mutex;
  std::weak_ptr<SharedGlContext> Current;
  bool ExitHandlerRegistered = false;
  std::vector<const void*> KeptUntilExit; // see SharedGlContext::dispose
};

Registry& registry()
{
  static Registry* const instance = new Registry;
  return *instance;
}

} // namespace

std::shared_ptr<SharedGlContext> SharedGlContext::acquire()
{
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.Mutex);
  if (std::shared_ptr<SharedGlContext> alive = r.Current.lock())
  {
    return alive;
  }
  std::shared_ptr<SharedGlContext> created(new SharedGlContext()); // may throw
  r.Current = created;
  if (!r.ExitHandlerRegistered)
  {
    // Registered only now, after eglInitialize registered Mesa's own atexit() teardown of its
    // displays: handlers run in reverse order, so ours runs first, while EGL is still whole.
    // (glvnd's libEGL tears its vendors down later still, from its ELF destructor.)
    r.ExitHandlerRegistered = std::atexit(&SharedGlContext::closeAtExit) == 0;
  }
  return created;
}

SharedGlContext::SharedGlContext()
{
  Thread.run([this] {
    Context = std::make_unique<HeadlessGlContext>(); // may throw GpuUnavailableError
    ContextOpen = true;
  });
  Renderer = Context->renderer();
  Version = Context->version();
}

SharedGlContext::~SharedGlContext()
{
  // GL objects die on the thread that owns their context, and so does the context. Every
  // simulation using it is gone (it held a reference), so the queue holds nothing of theirs.
  Thread.run([this] { closeContext(); });
}

void SharedGlContext::closeContext()
{
  Context.reset(); // not current, destroyed, eglReleaseThread (see egl_context.cpp)
  ContextOpen = false;
}

void SharedGlContext::throwIfClosed() const
{
  if (!ContextOpen)
  {
    throw GpuUnavailableError("The GPU context was closed: the process is exiting.");
  }
}

void SharedGlContext::keepUntilExit(const void* object)
{
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.Mutex);
  r.KeptUntilExit.push_back(object); // still reachable: not a leak, the process is ending
}

void SharedGlContext::closeAtExit()
{
  std::shared_ptr<SharedGlContext> alive;
  {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.Mutex);
    alive = r.Current.lock();
  }
  if (alive)
  {
    // Simulations still alive at exit (to be destroyed by static destructors, or never): close
    // the context now, while the driver is intact; they then dispose of their GL objects
    // without GL (dispose()). The thread is joined when the last of them lets go.
    alive->Thread.run([&alive] { alive->closeContext(); });
  }
}

} // namespace softbody::gpu
