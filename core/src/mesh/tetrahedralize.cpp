// Closed surface -> tets with TetGen. TetGen is built with TETLIBRARY: its fatal paths throw an
// int (terminatetetgen) instead of calling exit(), so every failure here becomes an
// InvalidInputError and the host process (ParaView) survives.
#include "softbody/mesh/tetrahedralize.h"

#include "softbody/common/errors.h"

#include <tetgen.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <new>
#include <sstream>
#include <unordered_map>

namespace softbody
{
namespace
{

std::uint64_t edgeKey(std::int32_t a, std::int32_t b)
{
  const auto lo = static_cast<std::uint32_t>(std::min(a, b));
  const auto hi = static_cast<std::uint32_t>(std::max(a, b));
  return (std::uint64_t(lo) << 32) | hi;
}

/// TetGen's terminatetetgen codes (tetgen.h), told as what the user can do about them.
std::string tetgenFailure(int code)
{
  switch (code)
  {
    case 1:
      return "TetGen ran out of memory; use a coarser setting (larger Max Tet Volume).";
    case 3:
      return "the surface intersects itself; repair it (e.g. in MeshLab) before tetrahedralizing.";
    case 4:
      return "TetGen found a very small input feature or nearly coincident points; clean the "
             "surface (merge points, remove tiny triangles).";
    case 5:
      return "the surface has two overlapping (duplicated) triangles; clean the surface.";
    case 10:
      return "TetGen found a vertex lying on a segment or facet it should not; clean the surface.";
    default:
      return "TetGen failed with internal error code " + std::to_string(code) +
        "; try other quality settings or clean the surface.";
  }
}

/// The TetGen switch string: p (a PLC), z (0-based), q/a/Y/Q from the options.
std::string tetgenSwitches(const TetrahedralizeOptions& options)
{
  std::ostringstream s;
  s.precision(17);
  s << "pz";
  if (options.maxRadiusEdgeRatio > 0.0)
  {
    s << "q" << options.maxRadiusEdgeRatio;
    if (options.minDihedralAngle > 0.0)
    {
      s << "/" << options.minDihedralAngle;
    }
  }
  if (options.maxTetVolume > 0.0)
  {
    s << "a" << options.maxTetVolume;
  }
  if (options.maxAddedPoints > 0)
  {
    s << "S" << options.maxAddedPoints;
  }
  if (options.preserveBoundary)
  {
    s << "Y";
  }
  if (options.quiet)
  {
    s << "Q";
  }
  return s.str();
}

void validateOptions(const TetrahedralizeOptions& o)
{
  // !(x >= 0) also rejects NaN.
  if (!(o.maxRadiusEdgeRatio >= 0.0) || !std::isfinite(o.maxRadiusEdgeRatio) ||
    (o.maxRadiusEdgeRatio > 0.0 && o.maxRadiusEdgeRatio < 1.0))
  {
    throw InvalidInputError("MaxRadiusEdgeRatio must be 0 (no refinement) or >= 1; TetGen "
                            "needs about 1.1 or more to finish (got " +
      std::to_string(o.maxRadiusEdgeRatio) + ").");
  }
  if (!(o.minDihedralAngle >= 0.0) || !(o.minDihedralAngle < 70.0))
  {
    throw InvalidInputError("MinDihedralAngle must be in [0, 70) degrees (got " +
      std::to_string(o.minDihedralAngle) + ").");
  }
  if (o.maxAddedPoints > static_cast<std::size_t>(std::numeric_limits<int>::max()))
  {
    throw InvalidInputError("MaxAddedPoints must be below 2^31 (TetGen counts in int).");
  }
  if (!(o.maxTetVolume >= 0.0) || !std::isfinite(o.maxTetVolume))
  {
    throw InvalidInputError("MaxTetVolume must be >= 0 (0 = unbounded; got " +
      std::to_string(o.maxTetVolume) + ").");
  }
}

} // namespace

SurfaceCheck checkClosedManifold(
  const std::vector<Vec3>& points, const std::vector<std::array<std::int32_t, 3>>& triangles)
{
  SurfaceCheck check;
  for (const Vec3& p : points)
  {
    check.nonFinitePoints += p.allFinite() ? 0 : 1;
  }
  // Per undirected edge: how many triangles use it, and the sum of its directions (+1 when a
  // triangle runs low->high, -1 otherwise). A closed, consistently oriented manifold has every
  // edge used twice in opposite directions: count 2, sum 0.
  struct Use
  {
    int count = 0;
    int direction = 0;
  };
  std::unordered_map<std::uint64_t, Use> edges;
  edges.reserve(triangles.size() * 2);
  const auto n = static_cast<std::int64_t>(points.size());
  for (const auto& t : triangles)
  {
    bool inRange = true;
    for (std::int32_t v : t)
    {
      inRange = inRange && v >= 0 && v < n;
    }
    if (!inRange)
    {
      ++check.badIndexTriangles;
      continue;
    }
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
    {
      ++check.degenerateTriangles;
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      const std::int32_t a = t[k], b = t[(k + 1) % 3];
      Use& use = edges[edgeKey(a, b)];
      ++use.count;
      use.direction += a < b ? 1 : -1;
    }
  }
  for (const auto& [key, use] : edges)
  {
    (void)key;
    if (use.count == 1)
    {
      ++check.boundaryEdges;
    }
    else if (use.count > 2)
    {
      ++check.nonManifoldEdges;
    }
    else if (use.direction != 0)
    {
      ++check.inconsistentEdges;
    }
  }
  return check;
}

TetMesh tetrahedralizeSurface(const std::vector<Vec3>& points,
  const std::vector<std::array<std::int32_t, 3>>& triangles, const TetrahedralizeOptions& options,
  TetrahedralizeStats* stats)
{
  validateOptions(options);
  if (triangles.size() < 4)
  {
    throw InvalidInputError("The surface has " + std::to_string(triangles.size()) +
      " triangles; a closed surface needs at least 4.");
  }
  const SurfaceCheck check = checkClosedManifold(points, triangles);
  if (!check.ok())
  {
    std::ostringstream msg;
    msg << "The surface is not a closed, manifold, consistently oriented triangle surface, so "
           "it bounds no volume TetGen can fill:";
    if (check.nonFinitePoints)
      msg << " " << check.nonFinitePoints << " points with NaN/infinite coordinates;";
    if (check.badIndexTriangles)
      msg << " " << check.badIndexTriangles << " triangles with missing points;";
    if (check.degenerateTriangles)
      msg << " " << check.degenerateTriangles << " degenerate triangles (repeated corner);";
    if (check.boundaryEdges)
      msg << " " << check.boundaryEdges << " boundary edges (the surface is open: fill its holes, or merge duplicated points first);";
    if (check.nonManifoldEdges)
      msg << " " << check.nonManifoldEdges
          << " non-manifold edges (shared by 3 or more triangles);";
    if (check.inconsistentEdges)
      msg << " " << check.inconsistentEdges
          << " edges with inconsistently oriented triangles (make the normals consistent);";
    msg << " of " << triangles.size() << " triangles.";
    throw InvalidInputError(msg.str());
  }

  // Only the points the triangles use go to TetGen: an unused point would become a vertex of
  // the mesh (inside) or be dropped silently (outside).
  std::vector<int> toTetgen(points.size(), -1);
  std::vector<Vec3> used;
  for (const auto& t : triangles)
  {
    for (std::int32_t v : t)
    {
      if (toTetgen[v] < 0)
      {
        toTetgen[v] = static_cast<int>(used.size());
        used.push_back(points[v]);
      }
    }
  }

  tetgenio in, out;
  try
  {
    in.firstnumber = 0;
    in.numberofpoints = static_cast<int>(used.size());
    in.pointlist = new REAL[3 * used.size()];
    for (std::size_t i = 0; i < used.size(); ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        in.pointlist[3 * i + c] = used[i][c];
      }
    }
    // One facet of one polygon per triangle; tetgenio's destructor frees all of it.
    in.numberoffacets = static_cast<int>(triangles.size());
    in.facetlist = new tetgenio::facet[triangles.size()];
    in.facetmarkerlist = nullptr;
    for (std::size_t f = 0; f < triangles.size(); ++f)
    {
      tetgenio::facet& facet = in.facetlist[f];
      tetgenio::init(&facet);
      facet.numberofpolygons = 1;
      facet.polygonlist = new tetgenio::polygon[1];
      tetgenio::init(&facet.polygonlist[0]);
      facet.polygonlist[0].numberofvertices = 3;
      facet.polygonlist[0].vertexlist = new int[3];
      for (int c = 0; c < 3; ++c)
      {
        facet.polygonlist[0].vertexlist[c] = toTetgen[triangles[f][c]];
      }
    }

    // TetGen 1.5 may crash (SIGSEGV, not a throw) when it meets a self-intersection while
    // meshing, so a diagnosis pass (switch d) looks for intersecting facets first; it reports
    // them as its output faces and meshes nothing.
    {
      tetgenio diagnosis;
      char detect[] = "pdzQ";
      ::tetrahedralize(detect, &in, &diagnosis);
      if (diagnosis.numberoftrifaces > 0)
      {
        throw InvalidInputError("Tetrahedralization failed: the surface intersects itself (" +
          std::to_string(diagnosis.numberoftrifaces) +
          " intersecting triangles); repair it (e.g. in MeshLab) before tetrahedralizing.");
      }
    }
    std::string switches = tetgenSwitches(options);
    ::tetrahedralize(&switches[0], &in, &out);
  }
  catch (int code)
  {
    // TetGen's own report went to stdout; ours says what to do.
    throw InvalidInputError("Tetrahedralization failed: " + tetgenFailure(code));
  }
  catch (const std::bad_alloc&)
  {
    throw InvalidInputError("Tetrahedralization failed: " + tetgenFailure(1));
  }

  if (out.numberoftetrahedra <= 0 || out.numberofcorners < 4 || !out.tetrahedronlist)
  {
    throw InvalidInputError("TetGen produced no tetrahedra: the surface encloses no volume "
                            "(is it flat, or inside out?).");
  }
  TetMesh mesh;
  mesh.points.resize(static_cast<std::size_t>(out.numberofpoints));
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    mesh.points[i] = Vec3(out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]);
  }
  mesh.tets.resize(static_cast<std::size_t>(out.numberoftetrahedra));
  const std::size_t stride = static_cast<std::size_t>(out.numberofcorners);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
  {
    Tet tet;
    for (int c = 0; c < 4; ++c)
    {
      tet[c] = out.tetrahedronlist[stride * t + c] - out.firstnumber;
    }
    // TetGen's own convention is the opposite orientation; whatever it is, ours is positive.
    if (signedTetVolume(mesh.points[tet[0]], mesh.points[tet[1]], mesh.points[tet[2]],
          mesh.points[tet[3]]) < 0.0)
    {
      std::swap(tet[2], tet[3]);
    }
    mesh.tets[t] = tet;
  }
  if (stats)
  {
    stats->surfacePoints = used.size();
    stats->addedPoints = mesh.points.size() > used.size() ? mesh.points.size() - used.size() : 0;
    stats->addedPointsLimitReached =
      options.maxAddedPoints > 0 && stats->addedPoints >= options.maxAddedPoints;
  }
  return mesh;
}

} // namespace softbody
