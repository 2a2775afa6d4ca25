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
#include <span>
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

/// Edges that query the other bodies' trees together, with their tree node's box (the highest
/// nodes of at most this many; TriangleBvh::groups): one descent per group instead of one per
/// edge, and each edge then box-tests what its group found. bench_collision_scenes' ten piled
/// tori at 1 thread, detection per frame: 120, 118, 116, 121, 125 and 138 ms at 4, 8, 16, 32,
/// 64 and 128 edges per group (one run each; the cloth folding onto itself is flat from 4 to 16).
constexpr std::uint32_t kEdgesPerGroup = 16;

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
      for (std::uint32_t node : BodyEdgeBvh[b].groups(kEdgesPerGroup))
      {
        EdgeGroups.push_back({ static_cast<std::uint32_t>(b), node });
      }
    }
  }
  if (!EdgeBvhsBuilt)
  {
    BodyLastEdge.assign(BodyEdges.size(), -1);
    for (std::size_t b = 0; b < BodyEdges.size(); ++b)
    {
      BodyLastEdge[b] = BodyEdges[b].empty() ? -1 : BodyEdges[b].back(); // listed in ascending order
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

void CollisionDetector::detectEdgeGroup(std::size_t group, const std::vector<Vec3>& start,
  const std::vector<Vec3>& predicted, Candidates& candidates, std::vector<std::int32_t>& near, ContactSet& found) const
{
  // Every edge the group's box (widened by the thickness) overlaps, per body in slot order and
  // in each tree's depth-first order: what each of the group's edges would find with its own
  // box is a subset of these in the same order, and testEdgePair's box test picks it out. So
  // each edge meets the same candidates in the same order as if it had queried alone.
  const auto [slot, node] = EdgeGroups[group];
  const TriangleBvh& tree = BodyEdgeBvh[slot];
  const std::vector<std::int32_t>& groupEdges = BodyEdges[slot];
  const std::span<const std::int32_t> items = tree.nodeItems(node);
  std::int32_t first = groupEdges[static_cast<std::size_t>(items[0])];
  for (std::int32_t item : items)
  {
    first = std::min(first, groupEdges[static_cast<std::size_t>(item)]);
  }
  Aabb query = tree.nodeBox(node);
  query.inflate(Margin);
  near.clear();
  for (std::size_t body = 0; body < BodyEdges.size(); ++body)
  {
    if ((body == slot && !detectsSelf()) || BodyLastEdge[body] <= first)
    {
      continue; // its own body without self collisions; or no edge after the group's first (each pair once)
    }
    const std::vector<std::int32_t>& bodyEdges = BodyEdges[body];
    BodyEdgeBvh[body].forEachOverlapping(
      query, [&](std::int32_t item) { near.push_back(bodyEdges[static_cast<std::size_t>(item)]); });
  }
  for (std::int32_t item : items)
  {
    const auto e = static_cast<std::size_t>(groupEdges[static_cast<std::size_t>(item)]);
    candidates.found.clear();
    for (std::int32_t other : near)
    {
      if (static_cast<std::size_t>(other) > e) // each pair once
      {
        testEdgePair(e, static_cast<std::size_t>(other), start, predicted, candidates);
      }
    }
    if (!candidates.found.empty())
    {
      reduceCandidates(candidates.found, candidates.order, candidates.kept, found);
    }
  }
}

void CollisionDetector::detectEdges(
  BroadPhase kind, const std::vector<Vec3>& start, const std::vector<Vec3>& predicted, ContactSet& out)
{
  // Blocks of edges (brute force) or the trees' edge groups, each with its own output: the
  // concatenation, sorted below, is the same at any thread count.
  // (Groups in blocks of several: each block reuses one candidate list and one `near` list.)
  constexpr std::size_t kBlock = 256;
  constexpr std::size_t kGroupsPerBlock = 8;
  const bool bruteForce = kind == BroadPhase::BruteForce;
  const std::size_t blocks = bruteForce ? (Edges.size() + kBlock - 1) / kBlock
                                        : (EdgeGroups.size() + kGroupsPerBlock - 1) / kGroupsPerBlock;
  EdgeBlockContacts.resize(blocks);
  EdgeBlockExamined.assign(blocks, 0);
  parallelFor(blocks, 1, [&](std::size_t block) {
    Candidates candidates;
    ContactSet& found = EdgeBlockContacts[block];
    found.clear();
    if (!bruteForce)
    {
      std::vector<std::int32_t> near;
      const std::size_t last = std::min(EdgeGroups.size(), (block + 1) * kGroupsPerBlock);
      for (std::size_t group = block * kGroupsPerBlock; group < last; ++group)
      {
        detectEdgeGroup(group, start, predicted, candidates, near, found);
      }
      EdgeBlockExamined[block] = candidates.examined;
      return;
    }
    const std::size_t end = std::min(Edges.size(), (block + 1) * kBlock);
    for (std::size_t e = block * kBlock; e < end; ++e)
    {
      candidates.found.clear();
      for (std::size_t f = e + 1; f < Edges.size(); ++f)
      {
        testEdgePair(e, f, start, predicted, candidates);
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
