// Tets held by contacts: keeping the floor (or an obstacle) from crushing a body's bottom layer.
//
// Each iteration projects the contacts last, so it ends with the inequalities satisfied. But a
// contact moves its point alone, onto the surface, and a tet with corners held there is
// flattened or turned inside out by it whenever the solve has not yet carried the support up
// through the body: the TetGen ellipsoid of issue 14 resting on the floor at the default 10
// iterations x 1 substep kept 620 of its 19,019 tets inverted after 0.2 s, all in the bottom
// centimetre, even with the non-inversion inequality of the volume projection (pbd_kernels.h),
// because the contacts came after it. So after the last iteration, every tet with a corner in
// obstacle contact that is below the least volume is projected onto V >= least with none of
// its corners moving into a surface that holds it (uncrushHeldTet, pbd_contact_kernels.h):
// that cannot undo a contact. (After every iteration's contacts as well: the same counts on
// the ellipsoid, 14 against 13 inverted tets per frame over 1 s, at three times the cost of
// the contact stage.) The tets are few (those around the contact points), taken one after
// another in their input order, so the result is the same at any thread count and vertex
// ordering.

#include "softbody/pbd/pbd_simulation.h"

#include "softbody/mesh/graph_coloring.h"
#include "softbody/mesh/reorder.h"

#include <algorithm>

namespace softbody
{

void PbdSimulation::collectHeldTets()
{
  HeldTets.clear();
  for (std::int32_t point : HeldPoints)
  {
    ObstacleGroupOf[static_cast<std::size_t>(point)] = -1;
  }
  HeldPoints.clear();
  if (!Plan.runs(Stage::SolveVolumes))
  {
    return; // no volume to keep
  }
  if (PointTets.offsets.empty())
  {
    // Built once the tets' storage order is final (the first detection): point -> slots
    // 4 t + k of the stored tets, and stored tet -> input tet.
    std::vector<std::int32_t> corners(4 * Volumes.size());
    for (std::size_t t = 0; t < Volumes.size(); ++t)
    {
      std::copy(Volumes.tets[t].begin(), Volumes.tets[t].end(), corners.begin() + static_cast<std::ptrdiff_t>(4 * t));
    }
    PointTets = particleSlots(Predicted.size(), corners);
    ObstacleGroupOf.assign(Predicted.size(), -1);
    InputTetOf = VolumeSlot.empty() ? Order{} : inverseOrder(VolumeSlot);
  }
  for (std::size_t g = 0; g + 1 < ObstacleGroups.size(); ++g)
  {
    const std::int32_t point = Contacts[ObstacleGroups[g]].point;
    ObstacleGroupOf[static_cast<std::size_t>(point)] = static_cast<std::int32_t>(g);
    HeldPoints.push_back(point);
    const std::size_t p = static_cast<std::size_t>(point);
    for (std::int32_t k = PointTets.offsets[p]; k < PointTets.offsets[p + 1]; ++k)
    {
      HeldTets.push_back(PointTets.items[static_cast<std::size_t>(k)] / 4); // slot 4 t + corner
    }
  }
  // Taken in the order of the tets as given (not as stored, which depends on the vertex
  // ordering and the solver), so that the repair, a Gauss-Seidel of its own, does the same
  // operations whatever the storage.
  for (std::int32_t& t : HeldTets)
  {
    t = InputTetOf.empty() ? t : InputTetOf[static_cast<std::size_t>(t)];
  }
  std::sort(HeldTets.begin(), HeldTets.end());
  HeldTets.erase(std::unique(HeldTets.begin(), HeldTets.end()), HeldTets.end());
  for (std::int32_t& t : HeldTets)
  {
    t = VolumeSlot.empty() ? t : VolumeSlot[static_cast<std::size_t>(t)];
  }
}

std::size_t PbdSimulation::uncrushHeldTets()
{
  std::vector<Vec3>& x = Predicted;
  const std::vector<double>& w = InverseMass;
  std::size_t corrected = 0;
  for (std::int32_t stored : HeldTets)
  {
    const std::size_t t = static_cast<std::size_t>(stored);
    if (!Volumes.active(t))
    {
      continue; // a broken tet no longer holds its volume
    }
    const Tet& tet = Volumes.tets[t];
    std::array<HeldCorner, 4> held;
    for (int k = 0; k < 4; ++k)
    {
      const std::int32_t g = ObstacleGroupOf[static_cast<std::size_t>(tet[k])];
      if (g < 0)
      {
        continue;
      }
      // The point's obstacle contacts: its group up to its first body contact.
      const Contact* begin = Contacts.data() + ObstacleGroups[static_cast<std::size_t>(g)];
      const Contact* end = Contacts.data() + ObstacleGroups[static_cast<std::size_t>(g) + 1];
      held[k].begin = begin;
      held[k].end = std::find_if(begin, end, [](const Contact& c) { return c.kind != ContactKind::Obstacle; });
    }
    const std::array<Vec3, 4> dx = uncrushHeldTet({ x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]] },
      { w[tet[0]], w[tet[1]], w[tet[2]], w[tet[3]] }, kLeastVolumeFraction * Volumes.restVolume[t], held);
    if (dx[0].isZero(0.0) && dx[1].isZero(0.0) && dx[2].isZero(0.0) && dx[3].isZero(0.0))
    {
      continue;
    }
    ++corrected;
    for (int k = 0; k < 4; ++k)
    {
      x[tet[k]] += dx[k];
    }
  }
  return corrected;
}

void PbdSimulation::finishHeldTets()
{
  // Neighbouring held tets share corners, so one's correction can crush another again; the
  // last iteration's state is the step's, so the pass is repeated until none is corrected, at
  // most kHeldTetPasses times. On the ellipsoid of python.floor_faults (1 s, 101 frames) four
  // passes leave 13-17 inverted tets per frame on average (39-45 at most); more passes did not
  // leave fewer (README): the last few are a Gauss-Seidel among neighbours that converges
  // slowly, and `Substeps` removes them all (python.floor_faults).
  constexpr int kHeldTetPasses = 4;
  for (int pass = 0; pass < kHeldTetPasses; ++pass)
  {
    if (uncrushHeldTets() == 0)
    {
      break;
    }
  }
}

} // namespace softbody
