// Edge against edge: the contacts the point pass cannot see. Two bars crossed at right angles
// touch edge on edge, with every vertex of each far from the other's faces; vertex-triangle
// contacts alone let such edges pass through each other. Each pair of surface edges is tested
// once (at the smaller edge index), edges in fixed blocks with their own outputs, so the set
// is the same at any thread count and for every broad phase, as the point pass's is.
#include "softbody/collision/collision_detector.h"

#include "detector_candidates.h"
#include "softbody/collision/closest_point.h"
#include "softbody/collision/contact_reduction.h"
#include "softbody/collision/narrow_phase.h"
#include "softbody/common/parallel.h"

#include <algorithm>
#include <tuple>

namespace softbody
{
namespace
{

/// An edge contact's normal against the outward normals of the two edges' faces: a normal
/// that points into the second edge's body, or out of the first's through the first edge's
/// faces, means the edges were already inside each other at the start of the substep (bodies
/// placed overlapping). Keeping such a pair where it was would lock the bodies together; the
/// point-triangle contacts separate them instead (start_overlap.h). The slack admits edges
/// that graze each other side-on (normal and outward nearly perpendicular).
constexpr double kInsideSlack = 0.1;

struct EdgeEnds
{
  std::array<std::int32_t, 2> ends;
  std::int32_t triangle;
};

} // namespace

void CollisionDetector::buildSurfaceEdges()
{
  std::vector<EdgeEnds> all;
  all.reserve(3 * Geometry.surfaceTriangles.size());
  for (std::size_t t = 0; t < Geometry.surfaceTriangles.size(); ++t)
  {
    const auto& tri = Geometry.surfaceTriangles[t];
    for (int k = 0; k < 3; ++k)
    {
      const std::int32_t a = tri[k], b = tri[(k + 1) % 3];
      all.push_back({ { std::min(a, b), std::max(a, b) }, static_cast<std::int32_t>(t) });
    }
  }
  std::sort(all.begin(), all.end(),
    [](const EdgeEnds& x, const EdgeEnds& y) { return std::tie(x.ends, x.triangle) < std::tie(y.ends, y.triangle); });
  for (const EdgeEnds& e : all)
  {
    if (!Edges.empty() && Edges.back() == e.ends)
    {
      auto& faces = EdgeTriangles.back();
      if (faces[1] < 0)
      {
        faces[1] = e.triangle; // a third face (a non-manifold edge) adds nothing to the outside
      }
    }
    else
    {
      Edges.push_back(e.ends);
      EdgeTriangles.push_back({ e.triangle, -1 });
      EdgeBody.push_back(TriangleBody[static_cast<std::size_t>(e.triangle)]); // its faces' body
      EdgeTwoSided.push_back(0);
    }
    if (!Geometry.twoSided.empty() && Geometry.twoSided[static_cast<std::size_t>(e.triangle)])
    {
      EdgeTwoSided.back() = 1;
    }
  }
  BodyEdges.resize(SurfaceBodies.size()); // an edge's body has its triangles
  for (std::size_t e = 0; e < Edges.size(); ++e)
  {
    BodyEdges[surfaceSlot(EdgeBody[e])].push_back(static_cast<std::int32_t>(e));
  }
  BodyEdgeBvh.resize(BodyEdges.size());
}

bool CollisionDetector::detectsEdges() const
{
  return Settings.edgeContacts && detectsBodies() && !Edges.empty();
}

void CollisionDetector::prepareEdges(BroadPhase kind, const std::vector<Vec3>& start, const std::vector<Vec3>& predicted)
{
  const auto& triangles = Geometry.surfaceTriangles;
  EdgeReach.resize(Edges.size());
  EdgeOutward.resize(Edges.size());
  parallelFor(Edges.size(), 4096, [&](std::size_t e) {
    EdgeReach[e] = std::max(Displacement[Edges[e][0]], Displacement[Edges[e][1]]);
    Vec3 outward = Vec3::Zero();
    for (std::int32_t t : EdgeTriangles[e])
    {
      if (t >= 0)
      {
        const auto& tri = triangles[static_cast<std::size_t>(t)];
        const Vec3 area = (start[tri[1]] - start[tri[0]]).cross(start[tri[2]] - start[tri[0]]);
        outward += area.norm() > 0.0 ? Vec3(area.normalized()) : Vec3::Zero();
      }
    }
    EdgeOutward[e] = outward.norm() > 0.0 ? Vec3(outward.normalized()) : Vec3::Zero();
  });
  EdgeBoxes.resize(Edges.size());
  parallelFor(Edges.size(), 4096, [&](std::size_t e) {
    Aabb box;
    box.grow(predicted[Edges[e][0]]);
    box.grow(predicted[Edges[e][1]]);
    box.inflate(EdgeReach[e]);
    EdgeBoxes[e] = box;
  });
  if (kind == BroadPhase::BruteForce)
  {
    return;
  }
  for (std::size_t b = 0; b < BodyEdges.size(); ++b)
  {
    ItemBoxes.resize(BodyEdges[b].size());
    for (std::size_t k = 0; k < BodyEdges[b].size(); ++k)
    {
      ItemBoxes[k] = EdgeBoxes[static_cast<std::size_t>(BodyEdges[b][k])];
    }
    if (EdgeBvhsBuilt)
    {
      BodyEdgeBvh[b].refit(ItemBoxes);
    }
    else
    {
      BodyEdgeBvh[b].build(ItemBoxes);
    }
  }
  EdgeBvhsBuilt = true;
}

void CollisionDetector::testEdgePair(std::size_t edge, std::size_t other, const std::vector<Vec3>& start,
  const std::vector<Vec3>& predicted, Candidates& candidates) const
{
  const auto& a = Edges[edge];
  const auto& b = Edges[other];
  if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1])
  {
    return; // edges of one corner meet there, not as edges
  }
  const bool sameBody = EdgeBody[edge] == EdgeBody[other];
  if (sameBody ? !detectsSelf() : !detectsBodies())
  {
    return;
  }
  const double thickness = Margin; // surface vertices have no radius
  Aabb reach = EdgeBoxes[edge];
  reach.inflate(thickness);
  if (!reach.overlaps(EdgeBoxes[other]))
  {
    return; // farther apart than both motions and the thickness (brute force's quick reject)
  }
  ++candidates.examined;
  ContactCandidate c;
  const double query = thickness + EdgeReach[edge] + EdgeReach[other];
  if (!edgeEdgeContact({ predicted[a[0]], predicted[a[1]], predicted[b[0]], predicted[b[1]] },
        { start[a[0]], start[a[1]], start[b[0]], start[b[1]] }, thickness, query, c))
  {
    return;
  }
  if (sameBody)
  {
    // Rest filter: edges of one body within reach at rest (across a thin part) would be in
    // contact from the first step on. (After the distance test: most pairs end there.)
    const auto& rest = Geometry.rest;
    const SegmentPair w = closestPointsOfSegments(rest[a[0]], rest[a[1]], rest[b[0]], rest[b[1]]);
    const Vec3 gap = rest[a[0]] + w.s * (rest[a[1]] - rest[a[0]]) - rest[b[0]] - w.t * (rest[b[1]] - rest[b[0]]);
    if (gap.norm() <= thickness)
    {
      return;
    }
  }
  const Vec3& n = c.contact.normal;
  if (!EdgeTwoSided[edge] && !EdgeTwoSided[other] &&
    (n.dot(EdgeOutward[other]) < -kInsideSlack || n.dot(EdgeOutward[edge]) > kInsideSlack))
  {
    return; // already inside each other at the start (kInsideSlack)
  }
  c.contact.kind = ContactKind::EdgeEdge;
  c.contact.point = a[0];
  c.contact.other = { a[1], b[0], b[1] };
  c.contact.source = EdgeBody[other];
  c.corners = { b[0], b[1], -1 };
  candidates.found.push_back(c);
}

void CollisionDetector::detectEdges(
  BroadPhase kind, const std::vector<Vec3>& start, const std::vector<Vec3>& predicted, ContactSet& out)
{
  constexpr std::size_t kBlock = 256;
  const std::size_t blocks = (Edges.size() + kBlock - 1) / kBlock;
  EdgeBlockContacts.resize(blocks);
  EdgeBlockExamined.assign(blocks, 0);
  parallelFor(blocks, 1, [&](std::size_t block) {
    Candidates candidates;
    ContactSet& found = EdgeBlockContacts[block];
    found.clear();
    const std::size_t end = std::min(Edges.size(), (block + 1) * kBlock);
    for (std::size_t e = block * kBlock; e < end; ++e)
    {
      candidates.found.clear();
      if (kind == BroadPhase::BruteForce)
      {
        for (std::size_t f = e + 1; f < Edges.size(); ++f)
        {
          testEdgePair(e, f, start, predicted, candidates);
        }
      }
      else
      {
        // The edge's box widened by the thickness against the other bodies' trees (and its
        // own with self collisions): every edge whose box it overlaps may be within the query.
        Aabb query = EdgeBoxes[e];
        query.inflate(Margin);
        for (std::size_t body = 0; body < BodyEdges.size(); ++body)
        {
          const bool own = SurfaceBodies[body] == EdgeBody[e];
          if (own && !detectsSelf())
          {
            continue;
          }
          const std::vector<std::int32_t>& items = BodyEdges[body];
          BodyEdgeBvh[body].forEachOverlapping(query, [&](std::int32_t item) {
            const auto f = static_cast<std::size_t>(items[static_cast<std::size_t>(item)]);
            if (f > e) // each pair once
            {
              testEdgePair(e, f, start, predicted, candidates);
            }
          });
        }
      }
      if (!candidates.found.empty())
      {
        reduceCandidates(candidates.found, candidates.order, candidates.kept, found);
      }
    }
    EdgeBlockExamined[block] = candidates.examined;
  });
  EdgeContacts.clear();
  for (std::size_t block = 0; block < blocks; ++block)
  {
    EdgeContacts.insert(EdgeContacts.end(), EdgeBlockContacts[block].begin(), EdgeBlockContacts[block].end());
    Stats.edgePairs += EdgeBlockExamined[block];
  }
  Stats.candidatePairs += Stats.edgePairs;
  Stats.edgeContacts = EdgeContacts.size();
  if (EdgeContacts.empty())
  {
    return;
  }
  // Into the point pass's set, keeping its order (the responses read each point's obstacle
  // contacts as one run).
  std::sort(EdgeContacts.begin(), EdgeContacts.end(), contactBefore);
  const auto middle = static_cast<std::ptrdiff_t>(out.size());
  out.insert(out.end(), EdgeContacts.begin(), EdgeContacts.end());
  std::inplace_merge(out.begin(), out.begin() + middle, out.end(), contactBefore);
}

} // namespace softbody
