#include "softbody/mesh/tet_mesh.h"

#include "softbody/common/errors.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace softbody
{
namespace
{

double volumeOf(const TetMesh& mesh, const Tet& t)
{
  return signedTetVolume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]);
}

/// Dihedral angle [degrees] at edge (a, b) between the faces (a, b, c) and (a, b, d): the angle
/// between c and d projected onto the plane normal to the edge. atan2 of |u x v| and u.v stays
/// accurate near 0 and 180 degrees, where acos of a normalized dot product does not, and that
/// is where slivers live.
double dihedralAngleDegrees(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  constexpr double kDegreesPerRadian = 57.295779513082320876798;
  Vec3 e = b - a;
  const double length = e.norm();
  if (!(length > 0.0))
  {
    return 0.0;
  }
  e /= length;
  const Vec3 u = (c - a) - e * e.dot(c - a);
  const Vec3 v = (d - a) - e * e.dot(d - a);
  return std::atan2(u.cross(v).norm(), u.dot(v)) * kDegreesPerRadian;
}

} // namespace

bool tetIndicesValid(const Tet& tet, std::size_t pointCount)
{
  for (int i = 0; i < 4; ++i)
  {
    if (tet[i] < 0 || static_cast<std::size_t>(tet[i]) >= pointCount)
    {
      return false;
    }
    for (int j = 0; j < i; ++j)
    {
      if (tet[i] == tet[j])
      {
        return false;
      }
    }
  }
  return true;
}

std::array<double, 6> tetDihedralAnglesDegrees(
  const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3)
{
  // Edge (i, j) and the two corners opposite it, which span its two faces.
  return { dihedralAngleDegrees(p0, p1, p2, p3), dihedralAngleDegrees(p0, p2, p1, p3),
    dihedralAngleDegrees(p0, p3, p1, p2), dihedralAngleDegrees(p1, p2, p0, p3),
    dihedralAngleDegrees(p1, p3, p0, p2), dihedralAngleDegrees(p2, p3, p0, p1) };
}

double tetMinDihedralAngleDegrees(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3)
{
  const std::array<double, 6> angles = tetDihedralAnglesDegrees(p0, p1, p2, p3);
  return *std::min_element(angles.begin(), angles.end());
}

TetMeshReport inspectTetMesh(
  const TetMesh& mesh, double degenerateRelativeVolume, double minDihedralDegrees)
{
  TetMeshReport report;
  for (const Vec3& p : mesh.points)
  {
    if (!p.allFinite())
    {
      ++report.nonFinitePoints;
    }
  }

  std::vector<char> used(mesh.points.size(), 0);
  std::vector<double> volumes(mesh.tets.size(), 0.0);
  std::size_t validCount = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
  {
    const Tet& tet = mesh.tets[t];
    if (!tetIndicesValid(tet, mesh.points.size()))
    {
      ++report.badIndexTets;
      continue;
    }
    for (std::int32_t p : tet)
    {
      used[p] = 1;
    }
    volumes[t] = volumeOf(mesh, tet);
    report.totalVolume += std::abs(volumes[t]);
    ++validCount;
  }
  report.unusedPoints = static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
  if (validCount == 0 || report.nonFinitePoints > 0)
  {
    return report;
  }

  // Degenerate is relative to the mesh's own scale, so the test is unit-independent.
  const double threshold = degenerateRelativeVolume * report.totalVolume / double(validCount);
  report.minAbsVolume = report.totalVolume;
  report.minDihedralDegrees = 180.0;
  bool anyMeasured = false;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
  {
    if (!tetIndicesValid(mesh.tets[t], mesh.points.size()))
    {
      continue;
    }
    const double absVolume = std::abs(volumes[t]);
    report.minAbsVolume = std::min(report.minAbsVolume, absVolume);
    report.maxAbsVolume = std::max(report.maxAbsVolume, absVolume);
    if (absVolume <= threshold)
    {
      if (report.degenerateTets++ == 0)
      {
        report.firstDegenerateTet = static_cast<std::ptrdiff_t>(t);
      }
    }
    else
    {
      if (volumes[t] < 0.0 && report.invertedTets++ == 0)
      {
        report.firstInvertedTet = static_cast<std::ptrdiff_t>(t);
      }
      // A degenerate tet is not also counted as a sliver: it is refused for its volume first.
      const Tet& tet = mesh.tets[t];
      const double angle = tetMinDihedralAngleDegrees(
        mesh.points[tet[0]], mesh.points[tet[1]], mesh.points[tet[2]], mesh.points[tet[3]]);
      anyMeasured = true;
      if (angle < minDihedralDegrees)
      {
        ++report.sliverTets;
        if (report.worstSliverTet < 0 || angle < report.minDihedralDegrees)
        {
          report.worstSliverTet = static_cast<std::ptrdiff_t>(t);
        }
      }
      report.minDihedralDegrees = std::min(report.minDihedralDegrees, angle);
    }
  }
  if (!anyMeasured)
  {
    report.minDihedralDegrees = 0.0;
  }
  return report;
}

TetMesh prepareTetMesh(TetMesh mesh, InvertedTetPolicy policy, std::vector<std::string>& warnings)
{
  if (mesh.points.empty() || mesh.tets.empty())
  {
    throw InvalidInputError("The input mesh is empty: it has " + std::to_string(mesh.points.size()) +
      " points and " + std::to_string(mesh.tets.size()) + " tetrahedra.");
  }
  const TetMeshReport report = inspectTetMesh(mesh);
  if (report.nonFinitePoints > 0)
  {
    throw InvalidInputError(std::to_string(report.nonFinitePoints) +
      " points have NaN or infinite coordinates; fix or remove them before simulating.");
  }
  if (report.badIndexTets > 0)
  {
    throw InvalidInputError(std::to_string(report.badIndexTets) +
      " tetrahedra refer to missing points or repeat a point.");
  }
  if (report.degenerateTets > 0)
  {
    std::ostringstream message;
    message << report.degenerateTets << " tetrahedra are degenerate (volume below "
            << kDegenerateRelativeVolume << " of the mean; the first is cell "
            << report.firstDegenerateTet
            << "). Their volume forces would be unbounded: remesh the body's surface with Soft "
               "Body's Tetrahedralize Surface (TetGen) filter, or remove them (ParaView's Mesh "
               "Quality filter with the Volume measure shows them).";
    throw InvalidInputError(message.str());
  }
  if (report.sliverTets > 0)
  {
    std::ostringstream message;
    message << report.sliverTets << " of the " << mesh.tets.size()
            << " tetrahedra are slivers: their smallest dihedral angle is below the minimum of "
            << kMinDihedralDegrees << " degrees (the worst is " << report.minDihedralDegrees
            << " degrees, cell " << report.worstSliverTet
            << "). A sliver's volume forces are unbounded (volume ratios explode, the stable time "
               "step collapses). Use Soft Body's Tetrahedralize Surface (TetGen) filter to mesh "
               "the body's surface (Extract Surface first for a volume mesh); Delaunay 3D makes "
               "such slivers. Soft Body Mesh Quality's MinDihedralAngle cell array shows them.";
    throw InvalidInputError(message.str());
  }
  if (report.invertedTets > 0)
  {
    std::ostringstream message;
    message << report.invertedTets << " tetrahedra are inverted (negative volume; the first is "
            << "cell " << report.firstInvertedTet << ")";
    if (policy == InvertedTetPolicy::Refuse)
    {
      message << ". Set InvertedTets to Re-orient to simulate them with corrected orientation.";
      throw InvalidInputError(message.str());
    }
    // Swapping two corners flips the sign of the volume; the input itself is not touched.
    for (Tet& tet : mesh.tets)
    {
      if (volumeOf(mesh, tet) < 0.0)
      {
        std::swap(tet[2], tet[3]);
      }
    }
    message << "; they were re-oriented for the simulation.";
    warnings.push_back(message.str());
  }
  if (report.unusedPoints > 0)
  {
    warnings.push_back(std::to_string(report.unusedPoints) +
      " points belong to no tetrahedron; they have no mass and stay where they are.");
  }
  return mesh;
}

} // namespace softbody
