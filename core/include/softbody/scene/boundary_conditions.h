// The conditions of one body prepared for its stepper: which components of which points are
// held and where they must be at a time, the external forces at a state, and the reactions the
// supports give. Every method asks this one object, so a condition means the same thing in the
// explicit, implicit, static and particle solvers.
//
// Held components: a point whose x, y and z are all held is kinematic (inverse mass 0, moved by
// the stepper to where its condition puts it); a point with some held (a roller) keeps its mass
// and is free along the others. Loads are forces in newtons: Force conditions are dead loads
// (constant in direction), Pressure follows its deformed faces, Pull is a linear spring on the
// set's mass-weighted centroid.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/scene/conditions.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace softbody
{

/// The total force and moment one condition exerts on the body at a state (for Fixed and
/// Prescribed: the supports' reaction), about `center`, the set's current centroid.
struct ConditionTotal
{
  std::string name;
  ConditionKind kind = ConditionKind::Fixed;
  std::size_t pointCount = 0;
  Vec3 force{ 0.0, 0.0, 0.0 };  ///< [N]
  Vec3 moment{ 0.0, 0.0, 0.0 }; ///< [N m]
  Vec3 center{ 0.0, 0.0, 0.0 }; ///< [m]
};

/// What a stepper reports of its conditions at its current state.
struct ConditionReadout
{
  /// Per point [N]: the force the supports exert on it along its held components (0 on free
  /// components and free points). Empty when nothing is held.
  std::vector<Vec3> reactions;
  std::vector<ConditionTotal> totals; ///< one per condition, in the order given
};

/// Bit i set: component i of the point is held.
using AxisMask = std::uint8_t;
constexpr AxisMask kAllAxes = 7;

class BoundaryConditions
{
public:
  BoundaryConditions() = default;
  /// Validates `conditions` (validateConditions) against `mesh` (rest points and tets, whose
  /// boundary faces a Pressure or ByArea condition acts on) and adds the warnings a user should
  /// read: an empty set, a force that would accelerate the whole body by more than 1000 g
  /// (`totalMass` [kg] is the body's). The point masses come later (setMasses).
  BoundaryConditions(std::vector<Condition> conditions, const std::vector<Vec3>& restPoints,
    const std::vector<Tet>& tets, double totalMass, std::vector<std::string>& warnings);

  /// The points' masses [kg], which spread ByMass forces and weigh the Pull centroid.
  void setMasses(const std::vector<double>& mass);

  /// Whether `conditions` differ from these in their values only (the same kinds, sets and
  /// held components): what replaceValues accepts.
  bool sameStructure(const std::vector<Condition>& conditions) const;
  /// New values for the same conditions (a widget moved while the animation plays): forces,
  /// pressures, motions, pull targets and stiffnesses, profiles. Throws InvalidInputError for a
  /// bad value or when !sameStructure (the held points and the masses would change).
  void replaceValues(std::vector<Condition> conditions);

  bool empty() const { return Conditions.empty(); }
  const std::vector<Condition>& conditions() const { return Conditions; }

  /// Per point: which components are held (empty when none is).
  const std::vector<AxisMask>& heldAxes() const { return Held; }
  /// Per point: 1 where every component is held (such points get inverse mass 0).
  std::vector<char> fullyHeld() const;
  /// Whether some held point moves (a Prescribed condition): steppers then move them.
  bool movesPoints() const { return MovesPoints; }
  bool hasLoads() const { return HasLoads; }
  bool hasPressure() const { return HasPressure; }

  /// Sets the held components of x and v to their conditions' values at time t.
  void holdPoints(double t, std::vector<Vec3>& x, std::vector<Vec3>& v) const;
  /// The same for the positions only (a solver's starting point).
  void holdPositions(double t, std::vector<Vec3>& x) const;
  /// Zeroes the held components of `a` (accelerations or search directions).
  void filterHeld(std::vector<Vec3>& a) const;
  /// The held components' prescribed acceleration at t of point i [m/s^2] (0 for Fixed).
  Vec3 heldAcceleration(std::size_t i, double t) const;

  /// Adds every load at time t and positions x to `forces` [N].
  void addLoads(double t, const std::vector<Vec3>& x, std::vector<Vec3>& forces) const;
  /// The dead part of the loads at time t, with the pressure evaluated on the faces at x
  /// (the implicit solvers take it constant over a step): `forces` is resized and filled.
  void deadLoads(double t, const std::vector<Vec3>& x, std::vector<Vec3>& forces) const;
  /// The Pull springs at time t: their energy at x [J], adding their forces to `forces`.
  double addPullForces(double t, const std::vector<Vec3>& x, std::vector<Vec3>& forces) const;
  /// Per point, the scalar of the Pull springs' diagonal Hessian block k w_i^2 I at time t
  /// (their exact Hessian couples the set's points; Newton keeps this diagonal part, exact
  /// for a single point): `k` is resized and filled.
  void pullStiffness(double t, std::vector<double>& k) const;
  bool hasPull() const { return !PullPoints.empty(); }

  /// The reactions and totals at a state: `internal` are the body's elastic and damping forces
  /// at (x, v) [N]; a held point's reaction is m a_prescribed - internal - loads - m g on its
  /// held components (the force the support must give for the point to follow its condition).
  ConditionReadout readout(double t, const std::vector<Vec3>& x,
    const std::vector<Vec3>& internal, const std::vector<double>& mass, const Vec3& gravity) const;

private:
  struct Motion; // a Prescribed condition's rigid motion, evaluated at a time
  Vec3 heldPosition(const Condition& c, std::size_t i, double t) const;
  void addPressure(const Condition& c, std::size_t k, double t, const std::vector<Vec3>& x,
    std::vector<Vec3>& forces) const;
  void addForce(const Condition& c, std::size_t k, double t, std::vector<Vec3>& forces) const;
  void gatherFaces(std::size_t k); ///< FaceGathers[k] from Faces[k]
  /// holdPoints, and holdPositions when `v` is null.
  void holdComponents(double t, std::vector<Vec3>& x, std::vector<Vec3>* v) const;
  /// Adds the Force and Pressure conditions' forces at t and x.
  void addForcesAndPressures(double t, const std::vector<Vec3>& x, std::vector<Vec3>& forces) const;

  std::vector<Condition> Conditions;
  std::vector<Vec3> Rest;
  std::vector<AxisMask> Held;
  /// For each point, the condition that holds each component (-1: none).
  std::vector<std::array<std::int32_t, 3>> HeldBy;
  /// Per condition: the boundary faces with all corners in its set (Pressure, ByArea).
  std::vector<std::vector<std::array<std::int32_t, 3>>> Faces;
  /// Per condition, its faces gathered by corner: for the k-th corner point (FaceCorner),
  /// entries FaceOfCorner[CornerStart[k] .. CornerStart[k+1]) are its faces, in face order.
  /// The pressure pass sums each point's share in parallel and in a fixed order.
  struct FaceGather
  {
    std::vector<std::int32_t> corner, start, faces;
  };
  std::vector<FaceGather> FaceGathers;
  mutable std::vector<Vec3> FaceArea; ///< scratch: area vectors of one condition's faces
  std::vector<std::vector<double>> Weights; ///< per condition, per point of its set: share
  std::vector<std::size_t> PullPoints;      ///< conditions that are Pull springs
  std::vector<double> Mass;
  bool MovesPoints = false, HasLoads = false, HasPressure = false;
};

} // namespace softbody
