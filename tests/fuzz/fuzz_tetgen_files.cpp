// libFuzzer target: the TetGen .node/.ele reader (core/src/mesh/tetgen_files.cpp), which runs
// TetGen's own file loaders after checking the headers. TetGen reads files by name only, so
// each input is written to a private temporary folder as <dir>/m.node and <dir>/m.ele: the bytes
// before the first line "@@ele" form the .node file, the rest the .ele file (no marker: an
// empty .ele). The reader must return a mesh with valid indices or throw
// softbody::InvalidInputError.
#include "softbody/common/errors.h"
#include "softbody/mesh/mesh_io.h"

#include "fuzz_support.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include <unistd.h>

namespace
{

/// A private folder for the two files, removed at exit (one object: no order of destruction).
struct TempDir
{
  std::string path;
  TempDir()
  {
    const char* base = std::getenv("TMPDIR");
    path = std::string(base && *base ? base : "/tmp") + "/softbody_fuzz_XXXXXX";
    if (!::mkdtemp(path.data()))
    {
      std::perror("mkdtemp");
      std::abort();
    }
  }
  ~TempDir()
  {
    ::unlink((path + "/m.node").c_str());
    ::unlink((path + "/m.ele").c_str());
    ::rmdir(path.c_str());
  }
};

const std::string& tempDir()
{
  static const TempDir dir;
  return dir.path;
}

void writeFile(const std::string& path, std::string_view bytes)
{
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f)
  {
    std::perror(path.c_str());
    std::abort();
  }
  if (!bytes.empty())
  {
    std::fwrite(bytes.data(), 1, bytes.size(), f);
  }
  std::fclose(f);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view marker = "@@ele\n";
  std::string_view node = text, ele;
  if (text.substr(0, marker.size()) == marker)
  {
    node = {};
    ele = text.substr(marker.size());
  }
  else if (const std::size_t at = text.find("\n@@ele\n"); at != std::string_view::npos)
  {
    node = text.substr(0, at + 1);
    ele = text.substr(at + 1 + marker.size());
  }
  writeFile(tempDir() + "/m.node", node);
  writeFile(tempDir() + "/m.ele", ele);
  try
  {
    softbody::MeshFileInfo info;
    const softbody::TetMesh mesh = softbody::readTetGenMesh(tempDir() + "/m.ele", &info);
    softbody::fuzz::abortOnIndexOutOfRange(mesh);
  }
  catch (const softbody::InvalidInputError&)
  {
  }
  return 0;
}
