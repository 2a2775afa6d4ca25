// One compiled compute kernel: storage blocks bound by name, uniforms set by name, and a
// dispatch over a number of items. Create, use and destroy it on the GL thread.
#pragma once

#include "storage_buffer.h"

#include <GL/glcorearb.h>

#include <string>
#include <unordered_map>

namespace softbody::gpu
{

class ComputeProgram
{
public:
  /// Compiles common.glsl followed by `source`. Throws GpuUnavailableError with the driver's
  /// log when the kernel does not compile or link (e.g. a driver without fp64).
  ComputeProgram(const std::string& name, const char* source);
  ~ComputeProgram();
  ComputeProgram(const ComputeProgram&) = delete;
  ComputeProgram& operator=(const ComputeProgram&) = delete;

  /// Makes this the current program; the setters and dispatch below apply to it.
  void use() const;
  /// Binds `buffer` to the storage block named `block`. Blocks the compiler dropped as unused
  /// are skipped.
  void bind(const char* block, const StorageBuffer& buffer) const;
  void set(const char* uniform, double value) const;
  void set(const char* uniform, unsigned value) const;
  void set(const char* uniform, bool value) const;
  void set(const char* uniform, const double (&value)[3]) const;

  /// Runs one invocation per item (uniform itemCount = items), then makes the writes visible
  /// to the next kernel.
  void dispatch(std::size_t items) const;
  /// Work groups a dispatch of `items` uses (for kernels that write one value per group).
  static std::size_t groupCount(std::size_t items);

private:
  GLint uniformLocation(const char* uniform) const;

  std::string Name;
  GLuint Program = 0;
  std::unordered_map<std::string, GLuint> BlockBindings;
};

} // namespace softbody::gpu
