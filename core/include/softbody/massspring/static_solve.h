// The Static integrator: at each step's end time, the static equilibrium of the elastic forces,
// gravity and the fixed points, by Newton's method with line search on the elastic energy
// minus gravity's work (Implicit Euler's solve with inertia and damping dropped). It is what an
// engineer checks a model with and the accuracy lab's reference. Velocities are zero.
//
// A free body has no equilibrium (gravity accelerates it; without gravity any rigid motion of
// an equilibrium is another), so the body must be held by fixed points that stop every rigid
// motion: at least three not on one line. The floor alone does not hold it (a body on a
// frictionless plane slides, and friction is a history the static solve does not have).
#pragma once

#include "softbody/massspring/implicit_euler.h"

#include <memory>
#include <string>

namespace softbody
{

/// Empty when the fixed points (inverse mass 0) hold the body; else the reason it is not held,
/// quoting the count, for the user.
std::string staticHoldProblem(const std::vector<Vec3>& positions, const PointMasses& masses);

class StaticStepper final : public ImplicitIntegrator
{
public:
  /// Throws InvalidInputError when the body is not held (staticHoldProblem).
  StaticStepper(const Topology& topology, const BodyElements& elements,
    const PointMasses& masses, const std::vector<Vec3>& restPositions, const SceneSettings& scene,
    const std::vector<Vec3>& positions);

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
