// The quality report on the public meshes of ../shared/data (read with core's Gmsh reader):
// 6_tetra_bad.msh has one inverted tet, IPC's bunny.msh is full of slivers (worst ~0.23
// degrees). Skipped when the folder is absent.
#include "softbody/mesh/mesh_io.h"
#include "softbody/stability/stability_report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

using namespace softbody;

namespace
{
/// The report for a shared mesh, or nothing (the test is then skipped) when it is absent.
bool reportFor(const std::string& relativePath, MassSpringQualityReport& report)
{
#ifdef SOFTBODY_SHARED_DATA_DIR
  const std::string path = std::string(SOFTBODY_SHARED_DATA_DIR) + "/" + relativePath;
  if (!std::filesystem::exists(path))
  {
    return false;
  }
  report = computeMassSpringQuality(readGmshMesh(path), MaterialSettings(), Integrator::EulerCromer);
  // Printed so the numbers behind the README's claims can be re-measured.
  std::cout << relativePath << ": " << report.signedVolume.size() << " tets, inverted "
            << report.invertedTets << ", degenerate " << report.degenerateTets << ", slivers "
            << report.sliverTets << ", min dihedral " << report.minDihedralDegreesOverall
            << " deg; stable step " << report.stableTimeStep << " s -> "
            << report.truncatedStableTimeStep << " s (x" << report.stableStepGain
            << ") with MaxInverseMass " << report.suggestedMaxInverseMass << " 1/kg on "
            << report.truncatedPoints << " points" << std::endl;
  return true;
#else
  (void)relativePath;
  (void)report;
  return false;
#endif
}
} // namespace

TEST(MeshQualityFiles, SofaBadMeshHasOneInvertedTet)
{
  MassSpringQualityReport r;
  if (!reportFor("sofa/6_tetra_bad.msh", r))
  {
    GTEST_SKIP() << "shared data not present";
  }
  EXPECT_EQ(r.invertedTets, 1u);
  EXPECT_EQ(r.inverted.size(), 6u);
  EXPECT_GT(r.stableTimeStep, 0.0); // computed on the re-oriented copy
}

TEST(MeshQualityFiles, IpcBunnySliversAreFlagged)
{
  MassSpringQualityReport r;
  if (!reportFor("IPC/bunny.msh", r))
  {
    GTEST_SKIP() << "shared data not present";
  }
  EXPECT_GT(r.sliverTets, 0u);
  EXPECT_NEAR(r.minDihedralDegreesOverall, 0.23, 0.05);
  EXPECT_GE(r.stableStepGain, 1.0);
}
