// Tets held by contacts: keeping the floor (or an obstacle) from crushing a body's bottom layer.
//
// Each iteration projects the contacts last, so it ends with the inequalities satisfied. But a
// contact moves its point alone, onto the surface, and a tet with corners held there is
// flattened or turned inside out by it whenever the solve has not yet carried the support up
// through the body: without this pass the TetGen ellipsoid resting on the floor at the default
// 10 iterations x 1 substep keeps 620 of its 19,019 tets inverted after 0.2 s, all in the bottom
// centimetre, even with the non-inversion inequality of the volume projection (pbd_kernels.h),
// because the contacts come after it. So after the last iteration, every tet with a corner in
// obstacle contact that is below the least volume is projected onto V >= least with none of
// its corners moving into a surface that holds it (uncrushHeldTet, pbd_contact_kernels.h):
// that cannot undo a contact. (Doing it after every iteration's contacts as well gives the
// same counts on the ellipsoid, 14 against 13 inverted tets per frame over 1 s, at three times
// the cost of the contact stage.) Before that repair, while a held tet is still inverted, the
// contact region is iterated on by itself, bottom up (finishHeldTets). The tets are few (those around
// the contact points), taken one after another in their input order (the region's links and
// tets by rest height), so the result is the same at any thread count and vertex ordering.

#include "softbody/pbd/pbd_simulation.h"

#include "softbody/mesh/graph_coloring.h"
#include "softbody/mesh/reorder.h"
#include "softbody/pbd/pbd_solvers.h"

#include <algorithm>
#include <tuple>

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
  if (!Plan.runs(Stage::SolveVolumes) && !Plan.runs(Stage::SolveTetElasticity))
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
    PointLinks = particleSlots(Predicted.size(), flattenParticles(Links));
    LinkInRegion.assign(Links.size(), 0);
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

void PbdSimulation::collectContactRegion()
{
  RegionLinks.clear();
  for (std::int32_t t : HeldTets)
  {
    for (std::int32_t corner : Volumes.tets[static_cast<std::size_t>(t)])
    {
      const std::size_t p = static_cast<std::size_t>(corner);
      for (std::int32_t k = PointLinks.offsets[p]; k < PointLinks.offsets[p + 1]; ++k)
      {
        const std::size_t link = static_cast<std::size_t>(PointLinks.items[static_cast<std::size_t>(k)] / 2);
        if (!LinkInRegion[link])
        {
          LinkInRegion[link] = 1;
          RegionLinks.push_back(static_cast<std::int32_t>(link));
        }
      }
    }
  }
  // Bottom up, by the rest height of the link's midpoint against gravity (then its other rest
  // coordinates): a sweep in that order carries the support up through the region, and the
  // order depends on the geometry alone, not on the vertex numbering or the storage.
  const Vec3 up = Settings.gravity.squaredNorm() > 0.0 ? Vec3(-Settings.gravity.normalized()) : Vec3::UnitZ();
  auto key = [&](std::int32_t link) {
    const std::int32_t* ends = Links.particles(static_cast<std::size_t>(link));
    const Vec3 mid = Rest[static_cast<std::size_t>(ends[0])] + Rest[static_cast<std::size_t>(ends[1])];
    return std::make_tuple(mid.dot(up), mid.x(), mid.y(), mid.z());
  };
  std::sort(RegionLinks.begin(), RegionLinks.end(), [&](std::int32_t a, std::int32_t b) { return key(a) < key(b); });
  for (std::int32_t link : RegionLinks)
  {
    LinkInRegion[static_cast<std::size_t>(link)] = 0;
  }
  RegionTets = HeldTets;
  auto tetKey = [&](std::int32_t t) {
    const Tet& tet = Volumes.tets[static_cast<std::size_t>(t)];
    const Vec3 c = Rest[static_cast<std::size_t>(tet[0])] + Rest[static_cast<std::size_t>(tet[1])] +
      Rest[static_cast<std::size_t>(tet[2])] + Rest[static_cast<std::size_t>(tet[3])];
    return std::make_tuple(c.dot(up), c.x(), c.y(), c.z());
  };
  std::stable_sort(RegionTets.begin(), RegionTets.end(), [&](std::int32_t a, std::int32_t b) { return tetKey(a) < tetKey(b); });
}

bool PbdSimulation::contactRegionInverted() const
{
  const std::vector<Vec3>& x = Predicted;
  return std::any_of(HeldTets.begin(), HeldTets.end(), [&](std::int32_t stored) {
    const std::size_t t = static_cast<std::size_t>(stored);
    const Tet& tet = Volumes.tets[t];
    return Volumes.active(t) && signedTetVolume(x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]]) <= 0.0;
  });
}

void PbdSimulation::iterateContactRegion()
{
  for (std::int32_t link : RegionLinks)
  {
    detail::projectAndApply(Links, static_cast<std::size_t>(link), Predicted, InverseMass);
  }
  for (std::int32_t t : RegionTets)
  {
    if (TetElastic.size() > 0)
    {
      detail::projectAndApply(TetElastic, static_cast<std::size_t>(t), Predicted, InverseMass);
    }
    else
    {
      detail::projectAndApply(Volumes, static_cast<std::size_t>(t), Predicted, InverseMass);
    }
  }
  projectContacts();
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
  // First the region: while a held tet is inverted after the global iterations, the held tets
  // and every link at their corners, then the contacts, are iterated on by themselves, bottom
  // up, at most kRegionIterations times. What the repair below leaves inverted on its own on
  // the ellipsoid of python.floor_faults (10 iterations x 1 substep: 30 tets per frame on
  // average over the first second, 59 at most, all 2-7 mm above the floor and at most 5% of the
  // mesh's median volume; 40 global iterations leave 2, 4 substeps none) is where a resting
  // body's support has not yet reached up through the solve: the same constraints solved
  // further there, in the order that carries the support upward (XPBD's multipliers carry on),
  // leave none; where the solve has converged, nothing runs. Sweeping in storage order instead
  // also leaves none, but makes the result depend on the vertex ordering; tet by tet in input
  // order leaves 1-2 per frame.
  //
  // Then the repair. Neighbouring held tets share corners, so one's correction can crush
  // another again; the last iteration's state is the step's, so the pass is repeated until
  // none is corrected, at most kHeldTetPasses times (more passes leave no fewer: README).
  constexpr int kRegionIterations = 20;
  if (contactRegionInverted())
  {
    collectContactRegion(); // only when needed: a resting body that converged pays nothing more
    for (int round = 0; round < kRegionIterations && contactRegionInverted(); ++round)
    {
      iterateContactRegion();
    }
  }
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
