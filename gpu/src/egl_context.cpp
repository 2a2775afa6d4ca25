#include "egl_context.h"

#include "softbody/gpu/gpu_errors.h"

#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <cstring>
#include <sstream>
#include <vector>

namespace softbody::gpu
{
namespace
{

constexpr int kRequiredMajor = 4;
constexpr int kRequiredMinor = 3;

bool hasExtension(const char* list, const char* name)
{
  if (!list)
  {
    return false;
  }
  const std::size_t length = std::strlen(name);
  for (const char* p = std::strstr(list, name); p; p = std::strstr(p + length, name))
  {
    const bool startsWord = p == list || p[-1] == ' ';
    const bool endsWord = p[length] == '\0' || p[length] == ' ';
    if (startsWord && endsWord)
    {
      return true;
    }
  }
  return false;
}

std::string eglErrorName(EGLint error)
{
  switch (error)
  {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: break;
  }
  std::ostringstream name;
  name << "EGL error 0x" << std::hex << error;
  return name.str();
}

/// A candidate display with a name for messages.
struct Candidate
{
  EGLDisplay display;
  std::string name;
};

/// EGL devices first (hardware, then software), then Mesa's surfaceless platform.
std::vector<Candidate> candidateDisplays(std::string& why)
{
  std::vector<Candidate> candidates;
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!clientExtensions)
  {
    why += " no EGL client extensions (is an EGL vendor library installed?);";
    return candidates;
  }
  auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
    eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!getPlatformDisplay)
  {
    why += " eglGetPlatformDisplayEXT is missing;";
    return candidates;
  }

  if (hasExtension(clientExtensions, "EGL_EXT_platform_device"))
  {
    auto queryDevices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLint count = 0;
    if (queryDevices && queryDevices(0, nullptr, &count) && count > 0)
    {
      std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
      queryDevices(count, devices.data(), &count);
      std::vector<Candidate> software;
      for (EGLint d = 0; d < count; ++d)
      {
        const char* extensions =
          queryDeviceString ? queryDeviceString(devices[d], EGL_EXTENSIONS) : nullptr;
        const bool isSoftware = hasExtension(extensions, "EGL_MESA_device_software");
        EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[d], nullptr);
        const std::string name =
          "EGL device " + std::to_string(d) + (isSoftware ? " (software)" : " (hardware)");
        if (display == EGL_NO_DISPLAY)
        {
          why += " " + name + ": no display (" + eglErrorName(eglGetError()) + ");";
          continue;
        }
        (isSoftware ? software : candidates).push_back({ display, name });
      }
      candidates.insert(candidates.end(), software.begin(), software.end());
    }
    else
    {
      why += " no EGL devices;";
    }
  }
  else
  {
    why += " no EGL_EXT_platform_device;";
  }

  if (hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless"))
  {
    EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display != EGL_NO_DISPLAY)
    {
      candidates.push_back({ display, "Mesa surfaceless platform" });
    }
    else
    {
      why += " Mesa surfaceless platform: no display;";
    }
  }
  else
  {
    why += " no EGL_MESA_platform_surfaceless;";
  }
  return candidates;
}

} // namespace

HeadlessGlContext::HeadlessGlContext()
{
  std::string why;
  for (const Candidate& candidate : candidateDisplays(why))
  {
    if (tryDisplay(candidate.display, candidate.name, why))
    {
      return;
    }
  }
  // The tests recognize this message's start as "no GPU here" (skip rather than fail).
  throw GpuUnavailableError("No OpenGL " + std::to_string(kRequiredMajor) + "." +
    std::to_string(kRequiredMinor) + " core context through EGL (no EGL driver, or none "
    "offering it):" + why);
}

bool HeadlessGlContext::tryDisplay(EGLDisplay display, const std::string& name, std::string& why)
{
  auto fail = [&](const std::string& what) {
    why += " " + name + ": " + what + ";";
    return false;
  };
  // Displays are never terminated: platform displays are per-process singletons shared by
  // every context on the same device, and terminating one would pull it from under other
  // simulations. glvnd releases them at exit.
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor))
  {
    return fail("eglInitialize failed (" + eglErrorName(eglGetError()) + ")");
  }
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  if (!hasExtension(extensions, "EGL_KHR_surfaceless_context"))
  {
    return fail("no EGL_KHR_surfaceless_context");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) // the default is OpenGL ES
  {
    return fail("desktop OpenGL is not supported (" + eglErrorName(eglGetError()) + ")");
  }
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!hasExtension(extensions, "EGL_KHR_no_config_context"))
  {
    const EGLint configAttributes[] = { EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE,
      EGL_PBUFFER_BIT, EGL_NONE };
    EGLint configCount = 0;
    if (!eglChooseConfig(display, configAttributes, &config, 1, &configCount) || configCount < 1)
    {
      return fail("no OpenGL-renderable EGL config");
    }
  }
  const EGLint contextAttributes[] = { EGL_CONTEXT_MAJOR_VERSION, kRequiredMajor,
    EGL_CONTEXT_MINOR_VERSION, kRequiredMinor, EGL_CONTEXT_OPENGL_PROFILE_MASK,
    EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE };
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
  if (context == EGL_NO_CONTEXT)
  {
    return fail("no OpenGL " + std::to_string(kRequiredMajor) + "." +
      std::to_string(kRequiredMinor) + " core context (" + eglErrorName(eglGetError()) + ")");
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
  {
    const std::string error = eglErrorName(eglGetError());
    eglDestroyContext(display, context);
    return fail("eglMakeCurrent failed (" + error + ")");
  }
  GLint glMajor = 0, glMinor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &glMajor);
  glGetIntegerv(GL_MINOR_VERSION, &glMinor);
  if (glMajor < kRequiredMajor || (glMajor == kRequiredMajor && glMinor < kRequiredMinor))
  {
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
    return fail("the context is only OpenGL " + std::to_string(glMajor) + "." +
      std::to_string(glMinor));
  }
  Display = display;
  Context = context;
  const auto glString = [](GLenum which) {
    const GLubyte* value = glGetString(which);
    return value ? std::string(reinterpret_cast<const char*>(value)) : std::string("unknown");
  };
  Renderer = glString(GL_RENDERER);
  Version = glString(GL_VERSION);
  Source = name;
  return true;
}

HeadlessGlContext::~HeadlessGlContext()
{
  eglMakeCurrent(Display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(Display, Context);
  // Frees EGL's per-thread state of the owning thread (it is about to end).
  eglReleaseThread();
}

} // namespace softbody::gpu
