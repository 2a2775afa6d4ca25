#include "compute_program.h"

#include "softbody/gpu/gpu_errors.h"

#include "softbody_gpu_shaders.h"

#include <algorithm>
#include <vector>

namespace softbody::gpu
{
namespace
{

constexpr std::size_t kWorkgroupSize = 128; // WORKGROUP_SIZE in common.glsl
constexpr std::size_t kMaxGroupsPerDimension = 65535; // GL's guaranteed minimum

std::string shaderLog(GLuint shader)
{
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  return log.data();
}

std::string programLog(GLuint program)
{
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetProgramInfoLog(program, length, nullptr, log.data());
  return log.data();
}

} // namespace

ComputeProgram::ComputeProgram(const std::string& name, const char* source)
  : Name(name)
{
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  const char* sources[2] = { shaders::kCommonSource, source };
  glShaderSource(shader, 2, sources, nullptr);
  glCompileShader(shader);
  GLint compiled = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
  if (!compiled)
  {
    const std::string log = shaderLog(shader);
    glDeleteShader(shader);
    throw GpuUnavailableError("The GPU kernel '" + name + "' does not compile: " + log);
  }
  Program = glCreateProgram();
  glAttachShader(Program, shader);
  glLinkProgram(Program);
  glDeleteShader(shader); // flagged; freed with the program
  GLint linked = GL_FALSE;
  glGetProgramiv(Program, GL_LINK_STATUS, &linked);
  if (!linked)
  {
    const std::string log = programLog(Program);
    glDeleteProgram(Program);
    throw GpuUnavailableError("The GPU kernel '" + name + "' does not link: " + log);
  }

  // Storage-block name -> binding point, as the kernel declares them.
  GLint blockCount = 0;
  glGetProgramInterfaceiv(Program, GL_SHADER_STORAGE_BLOCK, GL_ACTIVE_RESOURCES, &blockCount);
  for (GLint b = 0; b < blockCount; ++b)
  {
    char blockName[128] = {};
    glGetProgramResourceName(Program, GL_SHADER_STORAGE_BLOCK, static_cast<GLuint>(b),
      sizeof(blockName), nullptr, blockName);
    const GLenum property = GL_BUFFER_BINDING;
    GLint binding = 0;
    glGetProgramResourceiv(
      Program, GL_SHADER_STORAGE_BLOCK, static_cast<GLuint>(b), 1, &property, 1, nullptr, &binding);
    BlockBindings[blockName] = static_cast<GLuint>(binding);
  }
}

ComputeProgram::~ComputeProgram()
{
  glDeleteProgram(Program);
}

void ComputeProgram::use() const
{
  glUseProgram(Program);
}

void ComputeProgram::bind(const char* block, const StorageBuffer& buffer) const
{
  const auto found = BlockBindings.find(block);
  if (found != BlockBindings.end())
  {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, found->second, buffer.id());
  }
}

GLint ComputeProgram::uniformLocation(const char* uniform) const
{
  // -1 (dropped as unused) makes the glUniform* calls no-ops, as intended.
  return glGetUniformLocation(Program, uniform);
}

void ComputeProgram::set(const char* uniform, double value) const
{
  glUniform1d(uniformLocation(uniform), value);
}

void ComputeProgram::set(const char* uniform, unsigned value) const
{
  glUniform1ui(uniformLocation(uniform), value);
}

void ComputeProgram::set(const char* uniform, bool value) const
{
  glUniform1i(uniformLocation(uniform), value ? 1 : 0);
}

void ComputeProgram::set(const char* uniform, const double (&value)[3]) const
{
  glUniform3dv(uniformLocation(uniform), 1, value);
}

namespace
{
struct Grid
{
  std::size_t x, y;
};
// Wide dispatches wrap into y (itemIndex() in common.glsl undoes it).
Grid gridFor(std::size_t items)
{
  const std::size_t groups = (items + kWorkgroupSize - 1) / kWorkgroupSize;
  const std::size_t x = std::min(groups, kMaxGroupsPerDimension);
  return { x, x == 0 ? 0 : (groups + x - 1) / x };
}
} // namespace

std::size_t ComputeProgram::groupCount(std::size_t items)
{
  const Grid grid = gridFor(items);
  return grid.x * grid.y;
}

void ComputeProgram::dispatch(std::size_t items) const
{
  if (items == 0)
  {
    return;
  }
  set("itemCount", static_cast<unsigned>(items));
  const Grid grid = gridFor(items);
  glDispatchCompute(static_cast<GLuint>(grid.x), static_cast<GLuint>(grid.y), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

} // namespace softbody::gpu
