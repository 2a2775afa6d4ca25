// The lab's stability meshes and the table of omega_max estimates on them:
// how tight the set-up's estimate is and what it costs.
#pragma once

#include "bench_meshes.h"

#include <string>
#include <vector>

namespace softbody::bench
{

/// The stability table's meshes: a thesis-like cube (11^3 cells of 1 cm) and the public meshes
/// (quick: armadillo_4k only; full: armadillo_4k, SOFA's two, IPC's bunny), each scaled to a
/// 0.2 m bounding-box diagonal so their steps are comparable.
std::vector<NamedMesh> stabilityMeshes(const std::string& dataDir, bool quick);

/// For each stability mesh (and, full run, the 180k-tet ellipsoid): the Gershgorin bound, the
/// Lanczos estimate at 10, 20 and 40 steps, and a reference omega_max (the top Ritz value after
/// 300 steps, a lower bound that has converged), with the estimate's set-up time against one force
/// evaluation. Writes <out>/frequency.csv; returns the Markdown table. Calls `fail` when an
/// estimate used by the set-up is below the reference.
std::string frequencyTable(const std::string& dataDir, const std::string& out, bool quick,
  void (*fail)(const std::string&));

} // namespace softbody::bench
