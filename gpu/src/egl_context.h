// A headless OpenGL 4.3+ core-profile context through EGL, without any window system.
#pragma once

#include <EGL/egl.h>

#include <string>

namespace softbody::gpu
{

/// Creates a context and makes it current on the constructing thread, which then owns it: GL
/// calls must come from that thread only (see GlThread). Displays tried in order:
///   1. EGL devices (EGL_EXT_platform_device), hardware ones before software ones
///      (EGL_MESA_device_software marks Mesa's llvmpipe device);
///   2. Mesa's surfaceless platform (EGL_MESA_platform_surfaceless).
/// Throws GpuUnavailableError listing why each candidate failed.
class HeadlessGlContext
{
public:
  HeadlessGlContext();
  ~HeadlessGlContext();
  HeadlessGlContext(const HeadlessGlContext&) = delete;
  HeadlessGlContext& operator=(const HeadlessGlContext&) = delete;

  const std::string& renderer() const { return Renderer; } ///< GL_RENDERER
  const std::string& version() const { return Version; }   ///< GL_VERSION
  const std::string& source() const { return Source; }     ///< which EGL display it came from

private:
  /// Tries one display; on failure returns false and says why in `why`.
  bool tryDisplay(EGLDisplay display, const std::string& name, std::string& why);

  EGLDisplay Display = EGL_NO_DISPLAY;
  EGLContext Context = EGL_NO_CONTEXT;
  std::string Renderer;
  std::string Version;
  std::string Source;
};

} // namespace softbody::gpu
