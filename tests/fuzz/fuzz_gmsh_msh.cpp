// libFuzzer target: the Gmsh .msh reader (core/src/mesh/gmsh_msh.cpp) on arbitrary bytes.
// The reader must return a mesh or throw softbody::InvalidInputError; anything else (a crash,
// an ASan report, another exception, a hang) is a finding. A returned mesh must be consistent:
// every tet index names one of its points.
#include "softbody/common/errors.h"
#include "softbody/mesh/mesh_io.h"

#include "fuzz_support.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size), std::ios::binary);
  try
  {
    softbody::MeshFileInfo info;
    const softbody::TetMesh mesh = softbody::readGmshMesh(in, "fuzz.msh", &info);
    softbody::fuzz::abortOnIndexOutOfRange(mesh);
  }
  catch (const softbody::InvalidInputError&)
  {
    // A refusal with a message: the expected outcome for most inputs.
  }
  return 0;
}
