// A mass-spring soft body on a tetrahedral mesh: owns the state and the step plan and advances
// in time. This is the whole contract the VTK filter (and the future GPU stepper) relies on.
#pragma once

#include "softbody/constraints.h"
#include "softbody/integrators.h"
#include "softbody/mass.h"
#include "softbody/mass_spring_forces.h"
#include "softbody/simulation.h"
#include "softbody/tet_mesh.h"

#include <string>
#include <vector>

namespace softbody
{

struct SceneSettings
{
  Integrator integrator = Integrator::EulerCromer;
  /// [s]; 0 = automatic: the largest stable step estimate times stabilitySafety.
  double timeStep = 0.0;
  double stabilitySafety = 0.9; ///< fraction of the estimated stable step used in auto mode
  Vec3 gravity{ 0.0, 0.0, -9.81 }; ///< [m/s^2]
  bool floorEnabled = false;
  FloorPlane floor;
  /// Strain limit: maximum l / l0 of a spring (> 1); 0 disables strain limiting.
  double strainLimit = 0.0;
  int strainLimitIterations = 4;
  InvertedTetPolicy invertedTets = InvertedTetPolicy::Reorient;
  /// A state is declared exploded when a spring grows past this factor of its rest length.
  double divergenceStretch = 100.0;
};

struct BodyDescription
{
  TetMesh mesh;
  std::vector<char> pinned; ///< empty, or one flag per mesh point (nonzero: pinned)
  MaterialSettings material;
};

class MassSpringSimulation final : public Simulation
{
public:
  /// Validates and prepares the body; throws InvalidInputError with a user-facing message.
  MassSpringSimulation(BodyDescription body, const SceneSettings& scene);

  AdvanceStatus advance(double endTime, const ProgressCallback& progress = {}) override;
  const DynamicState& state() const override { return State; }
  void restoreState(const DynamicState& snapshot) override;

  const std::vector<Vec3>& restPositions() const override { return Mesh.points; }
  const std::vector<double>& inverseMasses() const override { return Masses.inverseMass; }
  const std::vector<double>& masses() const { return Masses.mass; }
  double totalMass() const override { return Masses.totalMass; }
  const Topology& topology() const { return Topo; }
  const ElementConstants& elementConstants() const { return Constants; }

  /// Current over rest volume of each tet (in core's orientation: inverted input tets that
  /// were re-oriented report positive ratios).
  std::vector<double> tetVolumeRatios() const override;

  double stepSize() const override { return Step; }
  double estimatedStableStep() const override { return StableStep; }
  double highestFrequency() const { return OmegaMax; }   ///< bound [rad/s]

  /// Everything worth telling the user: re-oriented tets, clamped parameters, a step above
  /// the stability estimate, truncated inverse masses.
  const std::vector<std::string>& warnings() const override { return Warnings; }
  std::vector<StageTiming> stageTimings() const override;

private:
  class Forces;
  void stepOnce(double h);
  void checkDivergence() const;

  SceneSettings Scene;
  TetMesh Mesh;
  Topology Topo;
  ElementConstants Constants;
  PointMasses Masses;
  DynamicState State;
  IntegratorScratch IntegratorWork;
  StrainLimitScratch StrainWork;
  double Step = 0.0;
  double StableStep = 0.0;
  double OmegaMax = 0.0;
  std::vector<std::string> Warnings;
  mutable std::vector<double> StageSeconds; // forces, integrate, strain limit, floor, checks
  mutable ForceScratch ForceWork;
  mutable std::vector<Vec3> ForceBuffer;
};

} // namespace softbody
