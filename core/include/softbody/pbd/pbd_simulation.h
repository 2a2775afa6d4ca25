// Position-based dynamics (Mueller et al. 2007) and XPBD (Macklin et al. 2016) on particles
// linked by distance constraints (tet edges, cloth and lattice links) and tet volume
// constraints, with pins, contacts (the floor, obstacles, other bodies, itself) as inequality
// constraints with friction and restitution, and breakable and plastic links.
#pragma once

#include "softbody/collision/collision_detector.h"
#include "softbody/common/error_control.h"
#include "softbody/common/simulation.h"
#include "softbody/material/tet_elasticity.h"
#include "softbody/mesh/topology.h"
#include "softbody/scene/body.h"
#include "softbody/pbd/pbd_contact_kernels.h"
#include "softbody/pbd/pbd_constraints.h"
#include "softbody/pbd/pbd_settings.h"
#include "softbody/pbd/pbd_solvers.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace softbody
{

/// Convergence of the last step: iterations run and the residual after each.
struct PbdConvergence
{
  int iterations = 0;
  double residual = 0.0;              ///< after the last iteration
  std::vector<double> residualHistory; ///< after each iteration of the last substep
};

class PbdSimulation final : public Simulation
{
public:
  /// Validates and prepares; throws InvalidInputError with a user-facing message.
  PbdSimulation(Body body, const PbdSettings& settings);

  AdvanceStatus advance(double endTime, const ProgressCallback& progress = {}) override;
  /// The state; plastic rest lengths and broken flags are copied into it only when asked for.
  const DynamicState& state() const override;
  void restoreState(const DynamicState& snapshot) override;

  const std::vector<Vec3>& restPositions() const override { return Rest; }
  const std::vector<double>& inverseMasses() const override { return InverseMass; }
  double totalMass() const override { return TotalMass; }
  std::vector<double> tetVolumeRatios() const override;
  TetStressField stressField() const override;
  /// The supports' reactions (pbd_reactions.cpp): under XPBD with compliant constraints from
  /// the constraints' elastic forces at the current state; under PBD, and XPBD with a rigid
  /// constraint type, from the momentum the last substep's projections gave the held points
  /// (Gauss-Seidel solvers; averaged Jacobi has none).
  ConditionReadout conditionReadout() const override;
  double elasticEnergy() const override;
  double stepSize() const override { return Step; }
  double estimatedStableStep() const override { return 0.0; }
  const std::vector<std::string>& warnings() const override { return Warnings; }
  const StepPlan& stepPlan() const override { return Plan; }
  bool supportsObstacles() const override { return true; }
  /// With Collisions Off nothing is collided with, so the obstacles are kept out of the step.
  void setObstacles(std::vector<ObstacleSurface> obstacles, double endTime) override;
  bool setConditionValues(const std::vector<Condition>& conditions) override;
  /// XPBD's error-controlled steps (Scene::stepControl): each step of the controller runs the
  /// substeps and iterations of a fixed one.
  const StepControlReport* stepControlReport() const override
  {
    return Settings.stepControl == StepControl::ErrorControlled ? &StepReport : nullptr;
  }

  /// The contacts of the last substep (stepper numbering) and the detector that found them
  /// (null when the collision mode is Off).
  const ContactSet& contacts() const { return Contacts; }
  const CollisionDetector* collisionDetector() const { return Detector.get(); }

  /// Runs exactly one step of size h (tests and benchmarks drive the solver with this); it
  /// records its convergence when the plan has a residual stage.
  void step(double h);
  /// Records the residual after every iteration of every following step (benchmarks); by
  /// default only the last step of each advance() records it.
  void setRecordResidualsEveryStep(bool record) { RecordEveryStep = record; }
  const PbdConvergence& convergence() const { return Convergence; }
  /// Residual evaluations (one pass over the constraints each) since construction: the cost
  /// of convergence reporting and tolerances, and proof of when they ran.
  unsigned long long residualEvaluations() const { return ResidualEvaluations; }

  /// The batches as stored: links in input order and tets sorted by their vertices (locality),
  /// except with the parallel solver, which stores both color by color (use linkBroken /
  /// tetBroken to ask about an input link or tet).
  const DistanceBatch& links() const { return Links; }
  const VolumeBatch& volumes() const { return Volumes; }
  /// A continuum body's tets (MaterialModel Corotated or Stable Neo-Hookean), stored as volumes().
  const TetElasticBatch& tetElasticity() const { return TetElastic; }
  /// Links in input order are the tet edges (topology order), then the explicit links: explicit
  /// link j is link explicitLinkOffset() + j.
  std::size_t explicitLinkOffset() const { return ExplicitLinkOffset; }
  bool linkBroken(std::size_t link) const;
  bool tetBroken(std::size_t tet) const; ///< tet k in input order
  std::size_t brokenLinkCount() const;
  std::size_t colorCount() const; ///< colors of the link batch (parallel Gauss-Seidel)

private:
  /// One step of h; `recordConvergence`: record the residual history of its last substep.
  void stepOnce(double h, bool recordConvergence);
  void substep(double h, bool recordResiduals);
  void prepareParameters(double h);
  void predict(double h);
  /// Puts the held components of the predicted positions where their conditions say.
  void holdPredicted(double h);
  void solve(bool recordResiduals);
  void sweep();
  void projectAll(Stage stage);
  double residual() const;
  void updateVelocities(double h);
  void labelBodies();
  // Collisions (pbd_collisions.cpp, pbd_contact_response.cpp)
  void setUpCollisions(const std::vector<Tet>& tets,
    const std::vector<std::array<std::int32_t, 3>>& surfaceTriangles);
  bool collisionsActive() const; ///< anything to collide with: the plan's condition
  void replan();
  void detectContacts(double h);
  void projectContacts();
  /// Tets with a corner in obstacle contact, and their repair after the last iteration
  /// (pbd_held_tets.cpp).
  void collectHeldTets();
  std::size_t uncrushHeldTets(); ///< one pass; returns how many tets it corrected
  void finishHeldTets();         ///< passes after the last iteration, until none is corrected
  /// The contact region: the held tets and every link at their corners, iterated again with
  /// the contacts while a held tet stays inverted (pbd_held_tets.cpp).
  void collectContactRegion();
  bool contactRegionInverted() const;
  void iterateContactRegion();
  double contactResidual() const;
  void applyContactResponse(double h);
  void applyBodyRestitution(double h);
  void liftBodiesOntoFloor();
  void updateLinks(double h);
  void markBrokenTets();
  void storeLinksAndVolumesByColor();
  void storeLinksAndVolumesInStreams();
  /// Stores the batch in `order` (storage k takes the constraint now at order[k]) and composes
  /// LinkSlot / VolumeSlot and TetEdges with it.
  void storeLinksInOrder(const std::vector<std::int32_t>& order);
  void storeVolumesInOrder(const std::vector<std::int32_t>& order);
  void setComplianceFromElasticity(
    const Topology& topology, const std::vector<Vec3>& rest, const MaterialSettings& material);
  void setUpTetElasticity(
    const Topology& topology, const std::vector<Vec3>& rest, const MaterialSettings& material);
  void checkDivergence() const;
  AdvanceStatus advanceWithErrorControl(double endTime, const ProgressCallback& progress);
  /// Marks the points of the last substep's contacts and the points they touch.
  void markPointsInContact(std::vector<char>& mask) const;
  /// Reactions (pbd_reactions.cpp): whether every planned constraint type has a compliance, so
  /// that its force C / alpha along its gradient is defined, and those forces at x.
  bool constraintsHaveForces() const;
  void elasticForces(const std::vector<Vec3>& x, std::vector<Vec3>& forces) const;
  /// Where no constraint force is a function of the state: the forces the projections of the
  /// substep of size h just solved gave each point, lambda dC/dx / h^2, into State.
  void recordSupportForces(double h);

  PbdSettings Settings;
  std::vector<Vec3> Rest;
  BoundaryConditions Conditions; ///< loads and held points (scene/boundary_conditions.h)
  std::vector<Vec3> LoadForce; ///< the conditions' loads of the substep [N]
  std::vector<double> InverseMass;
  std::vector<double> PointMass; ///< [kg], held points included
  std::vector<char> Movable;
  std::vector<std::int32_t> BodyOf; ///< point -> connected body (links and tet edges)
  std::vector<std::int32_t> BodyFirstPoint; ///< body -> its lowest point index
  double TotalMass = 0.0;
  DistanceBatch Links;
  VolumeBatch Volumes;
  TetElasticBatch TetElastic; ///< empty unless a continuum model holds the tets
  /// The continuum model's tets in input order, for its energy and stress field.
  Topology ElasticTopology;
  TetElasticConstants ElasticConstants;
  AttachmentBatch Attachments;
  BatchSchedule LinkSchedule, VolumeSchedule, AttachmentSchedule;
  Csr TetEdges; ///< tet -> its 6 link indices, to mark tets of broken links
  std::size_t ExplicitLinkOffset = 0;
  std::vector<std::int32_t> LinkSlot, VolumeSlot; ///< input index -> storage index (empty: same)
  mutable StepPlan Plan; // timed from const members too (divergence check)
  mutable DynamicState State;
  mutable bool LinkStateStale = false; ///< Links.rest/broken changed since copied into State
  double Step = 0.0;
  std::vector<std::string> Warnings;
  bool ObstacleStartChecked = false; ///< noteObstacleStart ran on the obstacles of t = 0
  bool RecordEveryStep = false;
  /// Reactions from the multipliers (State.supportForces): something is held, no constraint
  /// force is a function of the state, and a Gauss-Seidel solver applies each projection whole.
  bool ReactionsFromMultipliers = false;
  PbdConvergence Convergence;
  StepControlReport StepReport;
  mutable unsigned long long ResidualEvaluations = 0;

  std::unique_ptr<CollisionDetector> Detector; ///< null when the collision mode is Off
  bool HasObstacles = false;

  // Per-step scratch
  std::vector<Vec3> Predicted;
  std::vector<Vec3> VelocityBefore; ///< velocity entering the solve (for restitution)
  ContactSet Contacts;                  ///< this substep's, sorted by point
  std::vector<ContactMultipliers> ContactLambda; ///< per contact, over the substep's iterations
  /// Obstacle contacts move only their own point: contacts [ObstacleGroups[g],
  /// ObstacleGroups[g + 1]) are one point's, solved as one parallel task.
  std::vector<std::size_t> ObstacleGroups;
  std::vector<std::size_t> BodyContacts; ///< point-point and point-triangle contacts, in order
  Csr PointTets; ///< point -> slots 4 t + k of the stored tets it is corner k of (first detection)
  std::vector<std::int32_t> ObstacleGroupOf; ///< point -> its ObstacleGroups index, -1: none
  std::vector<std::int32_t> HeldPoints;      ///< points with obstacle contacts this substep
  std::vector<std::int32_t> HeldTets;        ///< stored tets with a held corner, in input order
  std::vector<std::int32_t> InputTetOf;      ///< stored tet -> input tet (empty: the same)
  Csr PointLinks;                        ///< point -> slots 2 l + end of the stored links
  std::vector<std::int32_t> RegionLinks; ///< links at the held tets' corners, bottom up
  std::vector<std::int32_t> RegionTets;  ///< the held tets, bottom up
  std::vector<char> LinkInRegion;        ///< scratch of collectContactRegion
  double SubstepTime = 0.0;              ///< start of the current substep [s]
  double SubstepStep = 0.0;              ///< its length [s]
  std::vector<Vec3> JacobiScratch;
  double ParametersStep = -1.0;
};

} // namespace softbody
