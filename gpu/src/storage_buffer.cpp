#include "storage_buffer.h"

#include "softbody/gpu/gpu_errors.h"

#include <algorithm>
#include <utility>

namespace softbody::gpu
{

StorageBuffer::StorageBuffer(const std::string& name, std::size_t bytes, const void* data)
  : Bytes(bytes)
{
  GLint64 maxBlock = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
  if (maxBlock > 0 && bytes > static_cast<std::size_t>(maxBlock))
  {
    throw GpuUnavailableError("The GPU buffer '" + name + "' would need " +
      std::to_string(bytes >> 20) + " MiB, more than the device's largest storage block (" +
      std::to_string(maxBlock >> 20) + " MiB); the body is too large for this device.");
  }
  while (glGetError() != GL_NO_ERROR)
  {
  }
  glGenBuffers(1, &Id);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, Id);
  // 16 bytes at least: binding a zero-sized buffer is an error, and empty arrays (no tets
  // with a volume term, say) still get bound.
  const std::size_t allocated = std::max<std::size_t>(bytes, 16);
  glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(allocated), nullptr, GL_DYNAMIC_COPY);
  if (data && bytes > 0)
  {
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(bytes), data);
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  if (glGetError() != GL_NO_ERROR)
  {
    glDeleteBuffers(1, &Id);
    Id = 0;
    throw GpuUnavailableError("The GPU could not allocate the buffer '" + name + "' (" +
      std::to_string(bytes >> 20) + " MiB).");
  }
}

StorageBuffer::~StorageBuffer()
{
  if (Id != 0)
  {
    glDeleteBuffers(1, &Id);
  }
}

StorageBuffer::StorageBuffer(StorageBuffer&& other) noexcept
  : Id(std::exchange(other.Id, 0))
  , Bytes(std::exchange(other.Bytes, 0))
{
}

StorageBuffer& StorageBuffer::operator=(StorageBuffer&& other) noexcept
{
  if (this != &other)
  {
    if (Id != 0)
    {
      glDeleteBuffers(1, &Id);
    }
    Id = std::exchange(other.Id, 0);
    Bytes = std::exchange(other.Bytes, 0);
  }
  return *this;
}

void StorageBuffer::upload(const void* data, std::size_t bytes)
{
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, Id);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(std::min(bytes, Bytes)), data);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
}

void StorageBuffer::download(void* data, std::size_t bytes) const
{
  // Shader writes become visible to buffer reads only after this barrier.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, Id);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(std::min(bytes, Bytes)), data);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
}

void StorageBuffer::copyFrom(const StorageBuffer& source)
{
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT); // as download: shader writes before the copy
  glBindBuffer(GL_COPY_READ_BUFFER, source.Id);
  glBindBuffer(GL_COPY_WRITE_BUFFER, Id);
  glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0,
    static_cast<GLsizeiptr>(std::min(source.Bytes, Bytes)));
  glBindBuffer(GL_COPY_READ_BUFFER, 0);
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
}

} // namespace softbody::gpu
