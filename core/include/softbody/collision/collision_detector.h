// Contact detection for one simulation: the floor, the obstacle surfaces, the bodies against
// each other and each body against itself, through the chosen broad phase and an exact narrow
// phase (closest feature of a triangle, sphere against sphere). VTK-free; parallel and
// deterministic (the contact set is sorted, so it is the same at any thread count and for
// every broad phase).
#pragma once

#include "softbody/collision/boundary_triangles.h"
#include "softbody/collision/collision_settings.h"
#include "softbody/collision/contact.h"
#include "softbody/collision/obstacle.h"
#include "softbody/collision/point_octree.h"
#include "softbody/collision/triangle_bvh.h"
#include "softbody/collision/uniform_grid.h"
#include "softbody/common/floor_plane.h"

#include <array>
#include <cstdint>
#include <vector>

namespace softbody
{

/// The colliding geometry of the simulated points, fixed at set-up (in the stepper's point
/// numbering).
struct CollisionGeometry
{
  std::vector<Vec3> rest;               ///< rest positions (the self-collision rest filter)
  std::vector<std::int32_t> bodyOf;     ///< connected body of each point
  /// Per point: > 0 for particles collided as spheres (voxelized / particle bodies), 0 for
  /// vertices of tet bodies and cloth, which collide through surfaceTriangles.
  std::vector<double> radius;
  /// Outward-oriented boundary triangles of tet bodies (faces used by one tet) and the
  /// triangles of cloth; empty for pure particle bodies.
  std::vector<std::array<std::int32_t, 3>> surfaceTriangles;
  /// Per surface triangle, 1 when it is two-sided (cloth: a point is kept on the side it
  /// started the substep on), 0 when one-sided (a closed tet surface: points are pushed to
  /// its outside). Empty = all one-sided.
  std::vector<std::uint8_t> twoSided;
  /// Points that can touch anything: surface vertices and particles, and the interior points
  /// of tet bodies unless self collisions are on (pinned points included; the response
  /// leaves points of inverse mass 0 where they are).
  std::vector<std::int32_t> collidingPoints;
};

/// Counts of the last detect() call, for the plan's report and the benchmarks.
struct DetectionStats
{
  std::size_t candidatePairs = 0; ///< broad-phase pairs examined by the narrow phase
  std::size_t contacts = 0;
  std::size_t edgePairs = 0;    ///< of candidatePairs: edge pairs examined
  std::size_t edgeContacts = 0; ///< of contacts: edge against edge
  /// The most of one point: pairs examined by the narrow phase, and contacts kept (what the
  /// cost per point is bounded by; see kMostContactsPerSource in contact_reduction.h).
  std::size_t mostExaminedPerPoint = 0;
  std::size_t mostContactsPerPoint = 0;
  BroadPhase broadPhase = BroadPhase::BruteForce; ///< the kind used (Automatic resolved)
};

struct ContactCandidate; // narrow_phase.h

class CollisionDetector
{
public:
  /// Throws InvalidInputError (quoting the value) for a negative margin, friction or a
  /// restitution outside [0, 1].
  CollisionDetector(CollisionGeometry geometry, const CollisionSettings& settings,
    bool floorEnabled, const FloorPlane& floor);

  /// Replaces the obstacles (validated: finite vertices, indices in range, velocities empty or
  /// one per vertex; InvalidInputError otherwise). `endTime` is when `vertices` hold.
  void setObstacles(std::vector<ObstacleSurface> obstacles, double endTime);
  const std::vector<ObstacleSurface>& obstacles() const { return Obstacles; }

  /// The contacts of points whose motion from `start` to `predicted` (one substep, at time
  /// `time` to `time + h`) comes within the margin of something: the query is widened by each
  /// point's displacement, so no contact is missed inside a step (no tunnelling as long as the
  /// solver keeps the points on the detected side). Output sorted (see ContactSet).
  void detect(const std::vector<Vec3>& start, const std::vector<Vec3>& predicted, double time,
    double h, ContactSet& out);

  double margin() const { return Margin; } ///< resolved (automatic replaced) [m]
  const FloorPlane& floor() const { return Floor; } ///< with its normal normalized
  const CollisionGeometry& geometry() const { return Geometry; }
  const DetectionStats& stats() const { return Stats; }
  const CollisionSettings& settings() const { return Settings; }

private:
  struct Candidates; // one point's narrow-phase results (collision_detector.cpp)
  void prepareSubstep(const std::vector<Vec3>& start, const std::vector<Vec3>& predicted, double time, double h);
  BroadPhase resolveBroadPhase() const;
  void prepareBroadPhase(BroadPhase kind, const std::vector<Vec3>& predicted);
  /// The floor's contact of `point` at `predicted`, moved `displacement` over the substep.
  bool floorCandidate(std::int32_t point, const Vec3& predicted, double displacement, ContactCandidate& c) const;
  void collectBruteForce(std::size_t colliding, const std::vector<Vec3>& start,
    const std::vector<Vec3>& predicted, Candidates& candidates) const;
  void collectAccelerated(BroadPhase kind, std::size_t colliding, const std::vector<Vec3>& start,
    const std::vector<Vec3>& predicted, Candidates& candidates) const;
  void testObstacleTriangle(std::int32_t point, std::size_t obstacle, std::size_t triangle,
    const std::vector<Vec3>& predicted, Candidates& candidates) const;
  void testPointPoint(std::int32_t point, std::int32_t other, const std::vector<Vec3>& start,
    const std::vector<Vec3>& predicted, Candidates& candidates) const;
  void testPointTriangle(std::int32_t point, std::size_t triangle, const std::vector<Vec3>& start,
    const std::vector<Vec3>& predicted, Candidates& candidates) const;
  bool detectsBodies() const;
  bool detectsSelf() const;
  // Edge against edge (collision_detector_edges.cpp): the surface edges, fixed at set-up, and
  // the pass that finds their contacts after the point pass, merged into its sorted set.
  void buildSurfaceEdges();
  bool detectsEdges() const;
  void prepareEdges(BroadPhase kind, const std::vector<Vec3>& start, const std::vector<Vec3>& predicted);
  void testEdgePair(std::size_t edge, std::size_t other, const std::vector<Vec3>& start,
    const std::vector<Vec3>& predicted, Candidates& candidates) const;
  void detectEdges(BroadPhase kind, const std::vector<Vec3>& start, const std::vector<Vec3>& predicted, ContactSet& out);

  CollisionGeometry Geometry;
  std::vector<std::int32_t> Colliding;    ///< collidingPoints, sorted, without repeats
  std::vector<std::int32_t> TriangleBody; ///< body of each surface triangle
  // Per substep (prepareSubstep):
  double SubstepLength = 0.0;             ///< h [s]: how much penetration a start may shed (start_overlap.h)
  std::vector<double> Displacement;       ///< |predicted - start| per point [m]
  std::vector<double> TriangleReach;      ///< largest corner displacement per surface triangle [m]
  std::vector<std::vector<Vec3>> ObstacleNow; ///< obstacle vertices at the end of the substep
  std::vector<std::vector<double>> ObstacleReach; ///< largest corner displacement per obstacle triangle [m]
  bool HasParticles = false;              ///< some colliding point has a radius (point-point pairs exist)
  // Broad phases (all but BruteForce): points in a grid or an octree, triangles in BVHs.
  UniformGrid Grid;
  PointOctree Octree;
  std::vector<Vec3> CollidingPositions;   ///< predicted positions of Colliding
  std::vector<double> CollidingReach;     ///< r + displacement + margin / 2: pairs within the sum
  std::vector<std::int32_t> CollidingBody; ///< body per colliding point, the grid's groups (empty: self collisions on); fixed
  // Uniform grid: its pairs of colliding points (indices into Colliding), found once each by
  // the grid's half stencil and listed at the smaller index.
  void collectGridPairs();
  std::vector<std::vector<std::array<std::int32_t, 2>>> BlockPairs; ///< per block of grid entries
  std::vector<std::size_t> BlockPairCount;
  std::vector<std::size_t> BlockOffsets; ///< where each block's contacts go in the detected set
  std::vector<std::int32_t> PartnerStart; ///< point k's partners: Partners[PartnerStart[k] .. [k+1])
  std::vector<std::int32_t> Partners;
  std::vector<std::int32_t> PartnerNext;  ///< scratch of the counting sort
  /// The bodies that have surface triangles, sorted: slot k of the per-body trees below is body
  /// SurfaceBodies[k] (body numbers are the caller's, not necessarily 0..n-1).
  std::vector<std::int32_t> SurfaceBodies;
  std::size_t surfaceSlot(std::int32_t body) const;
  /// One tree per body over its surface triangles (BodyTriangles[slot]: the triangles, in tree item
  /// order): a point searches only the bodies it may touch, so without self collisions the
  /// triangles around it on its own body, most of what a shared tree would return, are never
  /// visited.
  std::vector<std::vector<std::int32_t>> BodyTriangles;
  std::vector<TriangleBvh> BodySurfaceBvh;
  TriangleBvh ObstacleBvh;
  bool SurfaceBvhsBuilt = false;
  bool ObstacleBvhBuilt = false;
  std::vector<std::array<std::int32_t, 2>> ObstacleItems; ///< (obstacle, triangle) per obstacle BVH item
  std::vector<std::array<std::int32_t, 2>> Edges; ///< surface edges (smaller point first), sorted
  /// Per edge: the (up to two) surface triangles it borders, -1 where there is none.
  std::vector<std::array<std::int32_t, 2>> EdgeTriangles;
  std::vector<std::int32_t> EdgeBody;
  std::vector<std::uint8_t> EdgeTwoSided;  ///< borders a two-sided (cloth) triangle: no outside
  std::vector<Vec3> EdgeOutward;           ///< per substep: mean outward normal of its faces at the start
  std::vector<double> EdgeReach;           ///< per substep: largest end displacement [m]
  std::vector<Aabb> EdgeBoxes;             ///< per substep: predicted ends, widened by the reach
  /// One tree per body over its edges (BodyEdges[slot]: the edges, in tree item order), so an edge
  /// searches only the bodies it may collide with: without self collisions, its own body's
  /// edges (every one of its neighbours) are never visited.
  std::vector<std::vector<std::int32_t>> BodyEdges;
  std::vector<TriangleBvh> BodyEdgeBvh;
  bool EdgeBvhsBuilt = false;
  /// The edges' query groups (slot, node of that slot's edge tree), fixed with the trees'
  /// shape: each group queries the other trees once with its node's box (detectEdges).
  std::vector<std::array<std::uint32_t, 2>> EdgeGroups;
  std::vector<std::int32_t> BodyLastEdge;  ///< per slot: its largest edge index
  void detectEdgeGroup(std::size_t group, const std::vector<Vec3>& start, const std::vector<Vec3>& predicted,
    Candidates& candidates, std::vector<std::int32_t>& near, ContactSet& found) const;
  std::vector<ContactSet> EdgeBlockContacts;
  std::vector<std::size_t> EdgeBlockExamined;
  ContactSet EdgeContacts;
  std::vector<Aabb> ItemBoxes;            ///< scratch for the BVH refits
  std::vector<ContactSet> BlockContacts;  ///< per block of points, kept between detections
  std::vector<std::size_t> BlockExamined;
  std::vector<std::array<std::size_t, 2>> BlockMost; ///< per block: most examined, most contacts of a point

  CollisionSettings Settings;
  bool FloorEnabled = false;
  FloorPlane Floor;
  std::vector<ObstacleSurface> Obstacles;
  double ObstacleEndTime = 0.0;
  double Margin = 0.0;
  DetectionStats Stats;
};

} // namespace softbody
