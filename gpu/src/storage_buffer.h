// A shader storage buffer (SSBO) owned by RAII. Create, use and destroy it on the GL thread.
#pragma once

#include <GL/glcorearb.h>

#include <cstddef>
#include <string>
#include <vector>

namespace softbody::gpu
{

class StorageBuffer
{
public:
  StorageBuffer() = default;
  /// Allocates `bytes` (at least 16: zero-sized buffers cannot be bound), optionally filled
  /// from `data`. Throws GpuUnavailableError when the device refuses (out of memory, or larger
  /// than the largest storage block it supports); `name` goes into that message.
  StorageBuffer(const std::string& name, std::size_t bytes, const void* data = nullptr);
  ~StorageBuffer();
  StorageBuffer(StorageBuffer&& other) noexcept;
  StorageBuffer& operator=(StorageBuffer&& other) noexcept;
  StorageBuffer(const StorageBuffer&) = delete;
  StorageBuffer& operator=(const StorageBuffer&) = delete;

  GLuint id() const { return Id; }
  std::size_t bytes() const { return Bytes; }

  void upload(const void* data, std::size_t bytes);
  /// Waits for the kernels that wrote the buffer, then copies it out.
  void download(void* data, std::size_t bytes) const;
  /// Copies `source` (as many bytes as both hold) into this buffer on the GPU, after the
  /// kernels that wrote it.
  void copyFrom(const StorageBuffer& source);

  template <typename T>
  static StorageBuffer fromVector(const std::string& name, const std::vector<T>& values)
  {
    return StorageBuffer(name, values.size() * sizeof(T), values.empty() ? nullptr : values.data());
  }

private:
  GLuint Id = 0;
  std::size_t Bytes = 0;
};

} // namespace softbody::gpu
