// A mass-spring soft body on a tetrahedral mesh: owns the state and the step plan and advances
// in time. This is the whole contract the VTK filter (and the future GPU stepper) relies on.
#pragma once

#include "softbody/collision/collision_detector.h"
#include "softbody/common/error_control.h"
#include "softbody/common/simulation.h"
#include "softbody/massspring/contact_response.h"
#include "softbody/integrators/explicit_integrators.h"
#include "softbody/massspring/implicit_euler.h"
#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/massspring/mass_spring_settings.h"
#include "softbody/massspring/mass_spring_setup.h" // StepCost
#include "softbody/massspring/projective_dynamics.h"
#include "softbody/massspring/strain_limit.h"
#include "softbody/material/mass.h"
#include "softbody/material/tet_elastic_forces.h"

#include <memory>
#include <string>
#include <vector>

namespace softbody
{

class MassSpringSimulation final : public Simulation
{
public:
  /// Validates and prepares the body; throws InvalidInputError with a user-facing message.
  MassSpringSimulation(Body body, const SceneSettings& scene);
  // The implicit steppers keep references to this object's topology and constants.
  MassSpringSimulation(const MassSpringSimulation&) = delete;
  MassSpringSimulation& operator=(const MassSpringSimulation&) = delete;

  AdvanceStatus advance(double endTime, const ProgressCallback& progress = {}) override;
  const DynamicState& state() const override { return State; }
  void restoreState(const DynamicState& snapshot) override;

  const std::vector<Vec3>& restPositions() const override { return Mesh.points; }
  const std::vector<double>& inverseMasses() const override { return Masses.inverseMass; }
  const std::vector<double>& masses() const { return Masses.mass; }
  double totalMass() const override { return Masses.totalMass; }
  const Topology& topology() const { return Topo; }
  const ElementConstants& elementConstants() const { return Constants; }
  MaterialModel materialModel() const { return Model; }
  /// The continuum models' per-tet constants (empty for the spring network).
  const TetElasticConstants& tetElasticConstants() const { return TetConstants; }
  /// Green strain, Cauchy and von Mises stress and energy density per tet of the current state
  /// (continuum models; the spring network has no stress tensor and gets empty arrays).
  TetStressField stressField() const override;
  /// Kinetic plus elastic energy of the current state [J] (for tests and the accuracy lab).
  double mechanicalEnergy() const;
  double elasticEnergy() const override; ///< [J]

  /// Reactions at the held points and each condition's total force and moment, at the
  /// current state.
  ConditionReadout conditionReadout() const override;
  bool setConditionValues(const std::vector<Condition>& conditions) override;

  /// Current over rest volume of each tet (in core's orientation: inverted input tets that
  /// were re-oriented report positive ratios).
  std::vector<double> tetVolumeRatios() const override;

  double stepSize() const override { return Step; }
  double estimatedStableStep() const override { return StableStep; }
  double highestFrequency() const { return OmegaMax; }   ///< bound [rad/s]

  /// Everything worth telling the user: re-oriented tets, clamped parameters, a step above
  /// the stability estimate, truncated inverse masses.
  const std::vector<std::string>& warnings() const override { return Warnings; }
  /// Said before a run (implicit integrators with the floor): the warning that steps of `step`
  /// land the body on the floor faster than its elements can take in one step, with the step
  /// that avoids it, from the current positions and velocities; empty when they do not, with
  /// error-controlled steps (which shorten themselves) and with the automatic step, which is
  /// split where it would (contactPieces).
  std::string landingStepWarning(double step) const;
  const StepPlan& stepPlan() const override { return Plan; }
  std::string longRunWarning(double duration) const override;

  /// Obstacles are collided with (unless Collisions is Off, which ignores them): detected
  /// after each step and resolved like every contact (contact_response.h); the implicit
  /// integrators hold them inside their solve (contact_planes.h), as they hold the floor.
  bool supportsObstacles() const override { return true; }
  void setObstacles(std::vector<ObstacleSurface> obstacles, double endTime) override;
  /// The contacts of the last step and what their response did (tests, diagnostics); the
  /// detector is null with Collisions Off.
  const ContactSet& lastContacts() const { return Contacts; }
  const ContactResponseStats& lastContactResponse() const { return ContactStats; }
  const CollisionDetector* collisionDetector() const { return Detector.get(); }

  const StepControlReport* stepControlReport() const override
  {
    return Scene.stepControl == StepControl::ErrorControlled ? &StepReport : nullptr;
  }

  /// Convergence of the implicit integrators' solves; null for the explicit ones.
  const ImplicitConvergence* implicitConvergence() const;
  /// The Projective Dynamics stepper (factorization facts); null for other integrators.
  const ProjectiveDynamicsStepper* projectiveDynamics() const
  {
    return dynamic_cast<const ProjectiveDynamicsStepper*>(Implicit.get());
  }
  /// The implicit solve's coordinate preconditioner; null when it uses block Jacobi.
  const CoordinatePreconditioner* coordinatePreconditioner() const
  {
    return Implicit ? Implicit->coordinatePreconditioner() : nullptr;
  }

private:
  class Forces;
  /// The elastic and damping forces of the body's model at (x, v) [N].
  void internalForces(const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities,
    std::vector<Vec3>& forces) const;
  void stepOnce(double h);
  /// stepOnce, split into `contactPieces` shorter steps where that is more than one; `depth`
  /// counts the splits above this one.
  void stepSplittingContacts(double h, int depth);
  /// Into how many equal steps an automatic implicit step of h is split so that no point moves
  /// into its contact plane (the floor, an obstacle, another body) by more than its elements'
  /// size in one: such a step stops the point there while the points behind it move on, which
  /// crushes the elements between. 1 where the step is the user's (TimeStep > 0: told instead,
  /// landingStepWarning and fastContactSteps), error-controlled, or BDF2's (its history
  /// assumes the step it was given) or the static solve's.
  int contactPieces(double h) const;
  void integrateExplicit(double h);
  void integrateImplicit(double h);
  void checkDivergence() const;
  void resolveContacts(double h);
  /// One step of h (stepOnce first finds the obstacle planes of an implicit step).
  void takeStep(double h);
  /// Implicit integrators: the obstacle planes of the coming step of h (contact_planes.h).
  void findObstaclePlanes(double h);
  /// Implicit integrators: counts a step of h that moves a point into its contact plane by more
  /// than its elements' size (ImplicitConvergence::fastContactSteps).
  void noteFastApproach(double h);
  /// Implicit integrators: drops the obstacle contacts their solve already held.
  void dropObstacleContactsHeldInTheSolve();
  /// BDF2: restarts the history of the points the corrections after the solve moved on.
  void restartCorrectedHistories();
  /// Error control: marks the points in contact after the last step (on a contact plane of the
  /// implicit solve, or in a contact the response after the step found).
  void markPointsInContact(std::vector<char>& mask) const;
  /// Error control: the largest local position error of the step of h from `start` to the
  /// state, by the integrator's embedded estimate, over the points not marked in `skip` and
  /// the components no condition holds.
  double largestLocalError(const EmbeddedErrorEstimate& estimate, const DynamicState& start, double h,
    const std::vector<char>& skip);
  /// A point this fraction of its elements' size from its contact plane is in contact.
  static constexpr double kContactBand = 0.05;

  SceneSettings Scene;
  TetMesh Mesh;
  Topology Topo;
  MaterialModel Model = MaterialModel::SpringNetwork;
  ElementConstants Constants;
  TetElasticConstants TetConstants;
  PointMasses Masses;
  BoundaryConditions Conditions;
  DynamicState State;
  IntegratorScratch IntegratorWork;
  StrainLimitScratch StrainWork;
  StepCost Cost; // what a run's length depends on (longRunWarning)
  double Step = 0.0;
  double StableStep = 0.0;
  SelfWeight WeightStrain; ///< the set-up's, for a blow-up's message
  double OmegaMax = 0.0;
  std::vector<std::string> Warnings;
  bool ObstacleStartChecked = false; ///< noteObstacleStart ran on the obstacles of t = 0
  mutable StepPlan Plan; // stages and their timers (timed from const force evaluations)
  mutable ForceScratch ForceWork;
  mutable TetElasticScratch TetForceWork;
  mutable std::vector<Vec3> ForceBuffer;
  std::unique_ptr<ImplicitIntegrator> Implicit; // null for the explicit integrators
  // Contacts (Collisions not Off): the detector, the step's start positions it sweeps from,
  // the contacts found and what their response did.
  std::unique_ptr<CollisionDetector> Detector;
  bool HasObstacles = false; // the plan lists the collision stages for them
  bool SplitsContactSteps = false; ///< contactPieces may split: decided at set-up
  std::vector<Vec3> StepStart;
  ContactSet Contacts;
  // Implicit integrators with obstacles: the step's prediction and the contacts swept to it.
  std::vector<Vec3> Predicted;
  ContactSet PlaneContacts;
  ContactResponseStats ContactStats;
  StepControlReport StepReport;
  std::vector<Vec3> SolvedVelocities; ///< BDF2: the velocities the solve left
  std::vector<Vec3> LocalErrors;      ///< error control: each point's embedded estimate
};

} // namespace softbody
