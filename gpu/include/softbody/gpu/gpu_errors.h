// Exceptions of softbody_gpu.
#pragma once

#include <stdexcept>

namespace softbody::gpu
{

/// No usable GPU context: no EGL vendor or device, no OpenGL 4.3 core profile, a kernel that
/// does not compile, a body too large for the device's buffers. The message says which, for
/// the user (the filter falls back to the CPU and shows it).
class GpuUnavailableError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

} // namespace softbody::gpu
