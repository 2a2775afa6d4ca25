// The Static integrator: at each step's end time, the static equilibrium of the elastic forces,
// gravity and the fixed points, by Newton's method with line search on the elastic energy
// minus gravity's work (Implicit Euler's solve with inertia and damping dropped). It is what an
// engineer checks a model with and the accuracy lab's reference. Velocities are zero.
//
// A free body has no equilibrium (gravity accelerates it; without gravity any rigid motion of
// an equilibrium is another), so the body must be held by supports that stop every rigid
// motion: at least three fixed points not on one line, or rollers (some components held) on
// planes that together do, as symmetry planes in a finite-element model. The floor alone does not hold it (a body on a
// frictionless plane slides, and friction is a history the static solve does not have).
#pragma once

#include "softbody/massspring/implicit_euler.h"
#include "softbody/scene/boundary_conditions.h"

#include <memory>
#include <string>

namespace softbody
{

/// Empty when the supports (points of inverse mass 0, and the held components `heldAxes` gives
/// per point, which may be empty) stop every rigid motion; else the reason, naming a motion
/// they leave free and quoting their counts, for the user.
std::string staticHoldProblem(const std::vector<Vec3>& positions, const PointMasses& masses,
  const std::vector<AxisMask>& heldAxes);

class StaticStepper final : public ImplicitIntegrator
{
public:
  /// Throws InvalidInputError when the body is not held (staticHoldProblem).
  StaticStepper(const Topology& topology, const BodyElements& elements,
    const PointMasses& masses, const std::vector<Vec3>& restPositions, const SceneSettings& scene,
    const std::vector<Vec3>& positions, const BoundaryConditions* conditions);

  void step(double h, DynamicState& state, StepPlan& plan) override;
  const ImplicitConvergence& convergence() const override { return Newton->convergence(); }
  IncrementalPotential& potential() override { return Newton->potential(); }
  ContactPlanes& contactPlanes() override { return Newton->contactPlanes(); }
  std::string solverWarning() const override { return Newton->solverWarning(); }
  const CoordinatePreconditioner* coordinatePreconditioner() const override
  {
    return Newton->coordinatePreconditioner();
  }

private:
  // The body's constants without damping: at equilibrium nothing moves.
  ElementConstants Network;
  TetElasticConstants Tets;
  std::unique_ptr<ImplicitEulerStepper> Newton;
};

} // namespace softbody
