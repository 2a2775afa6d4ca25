// What a simulation collides with and how contacts respond: the Collisions, BroadPhase,
// CollisionMargin, friction and restitution settings shared by every method.
#pragma once

namespace softbody
{

/// Which contacts are detected. The floor plane (when enabled) and the obstacle surfaces are
/// always collided with unless the mode is Off.
enum class CollisionMode
{
  Off,                    ///< nothing, not even the floor
  Obstacles,              ///< the floor and the obstacle surfaces
  ObstaclesAndBodies,     ///< + each connected body against the others
  ObstaclesBodiesAndSelf  ///< + each body against itself (non-adjacent surface features)
};

/// The broad phase that finds candidate point-point and point-triangle pairs. Every kind
/// returns the same contact set (tests compare them with BruteForce); they differ in cost only.
enum class BroadPhase
{
  Automatic,  ///< chosen from the scene's size by measured cost (see bench_collision)
  BruteForce, ///< all pairs: the reference, O(n^2)
  UniformGrid,///< counting-sort hash grid, cell = largest query diameter
  Octree      ///< adaptive, for scenes of very different particle sizes
};

struct CollisionSettings
{
  CollisionMode mode = CollisionMode::Obstacles;
  BroadPhase broadPhase = BroadPhase::Automatic;
  /// Contact thickness kept between a point and what it touches [m], on top of the particle
  /// radii (Contact::thickness = margin + radii); 0 = automatic: a tenth of the mean particle
  /// radius for particle bodies, a tenth of the mean surface edge length for tet bodies and
  /// cloth, the smaller when both are present (CollisionDetector::margin() says the value).
  double margin = 0.0;
  /// Coulomb coefficients: a contact sticks while the tangential correction is below
  /// staticFriction times the normal one, and slides with dynamicFriction otherwise.
  double staticFriction = 0.0;
  double dynamicFriction = 0.0;
  /// In [0, 1]: the fraction of the normal approach speed kept after an impact.
  double restitution = 0.0;
  /// Edges of body surfaces against each other (collision_detector.h); off only to measure
  /// what they cost (bench_collision_scenes): vertex-triangle contacts alone let crossed
  /// edges pass through each other.
  bool edgeContacts = true;
  bool operator==(const CollisionSettings&) const = default;

  /// The rules every method and the filter read from the mode (decided here only).
  bool on() const { return mode != CollisionMode::Off; }
  bool bodiesCollide() const
  {
    return mode == CollisionMode::ObstaclesAndBodies || mode == CollisionMode::ObstaclesBodiesAndSelf;
  }
  bool selfCollides() const { return mode == CollisionMode::ObstaclesBodiesAndSelf; }
};

} // namespace softbody
