// The process's one GL thread and one headless context, shared by every GPU simulation.
//
// Why one, and not a thread and a context per simulation:
// - EGL displays are per-process singletons; Mesa keeps per-display and per-screen state (and
//   llvmpipe its worker threads) that every context of the process shares. Creating and
//   destroying a context per simulation, each on its own thread that then releases its EGL
//   thread state and exits, would multiply the create/destroy/thread-exit paths through the
//   driver and leave their order to whoever destroys filters last (a ParaView session can end
//   with eight filters torn down in whatever order its proxies go).
// - Process exit: Mesa's libEGL frees its displays in an atexit() handler, glvnd unloads its
//   vendors in an ELF destructor. A simulation destroyed by a static destructor after those ran
//   (ParaView singletons, Python finalization) would use EGL/GL on freed driver state. Here the
//   context is destroyed by our own atexit() handler, registered after EGL initialized and so
//   run before EGL's: the driver is still whole when the context goes, and simulations that
//   outlive it leave their GL objects to the process's end without calling GL.
//
// The shared object is reference counted: created by the first GPU simulation, destroyed (the
// context on its thread, then the thread joined) when the last one goes, and created anew by
// the next. Jobs of all simulations run one at a time on the one thread, so GL state is
// never shared across threads; each job binds everything it uses.
#pragma once

#include "gl_thread.h"

#include <memory>
#include <string>
#include <vector>

namespace softbody::gpu
{

class HeadlessGlContext;

class SharedGlContext
{
public:
  /// The shared context, created when none is alive. Throws GpuUnavailableError when no
  /// context can be made (the next call tries again).
  static std::shared_ptr<SharedGlContext> acquire();

  /// Destroys the context on the GL thread (unless process exit did already) and joins it.
  ~SharedGlContext();
  SharedGlContext(const SharedGlContext&) = delete;
  SharedGlContext& operator=(const SharedGlContext&) = delete;

  /// Runs `job` on the GL thread with the context current and returns its result (or rethrows
  /// its exception). Throws GpuUnavailableError once the context was closed at process exit.
  template <typename Job>
  auto run(Job&& job) -> std::invoke_result_t<Job>
  {
    return Thread.run([this, &job]() -> std::invoke_result_t<Job> {
      throwIfClosed();
      return job();
    });
  }

  /// Destroys `object` (which holds GL names) on the GL thread. After the context was closed at
  /// process exit its names are gone with it: the object is then kept, never destroyed (its
  /// destructor would call GL with no context), until the process ends.
  template <typename T>
  void dispose(std::unique_ptr<T>& object)
  {
    Thread.run([this, &object] {
      if (ContextOpen)
      {
        object.reset();
      }
      else if (object)
      {
        keepUntilExit(object.release());
      }
    });
  }

  const std::string& renderer() const { return Renderer; } ///< GL_RENDERER
  const std::string& version() const { return Version; }   ///< GL_VERSION

private:
  SharedGlContext(); // acquire() only
  void throwIfClosed() const;
  /// On the GL thread: destroys the context and releases the thread's EGL state.
  void closeContext();
  static void keepUntilExit(const void* object);
  static void closeAtExit();

  std::string Renderer;
  std::string Version;
  // Touched on the GL thread only.
  std::unique_ptr<HeadlessGlContext> Context;
  bool ContextOpen = false;
  GlThread Thread; // last: destroyed (joined) first
};

} // namespace softbody::gpu
