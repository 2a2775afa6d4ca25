// The step plan: the ordered stages one step of a simulation runs, each with its timer.
//
// A planner (mass_spring_plan.h, pbd_plan.h) decides once, from the settings and the body,
// which stages the scene needs; the stepper then asks the plan (`runs(Stage::Floor)`) instead
// of re-deciding from the settings, and times each stage into the plan. The same plan is what
// the filter reports ("Plan", "StageSeconds") and what the benchmarks read, by enum.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace softbody
{

enum class Stage
{
  // Mass-spring (CPU and GPU)
  Forces,      ///< spring (and tet volume) forces; timed inside the integrator's evaluations
  Integrate,   ///< the integrator, net of its force evaluations (and linear solves)
  LinearSolve, ///< implicit integrators: PCG (Implicit Euler) or Cholesky solves (Projective
               ///< Dynamics, with its factorization when the step size changes)
  StrainLimit, ///< Provot's strain limiting after the step
  Floor,       ///< floor contact after the step
  CollisionDetect, ///< every method: broad + narrow phase against floor, obstacles, bodies, self
  Contacts,        ///< mass-spring: contact projection and velocity response after the step
  // PBD / XPBD
  Predict,          ///< gravity and damping into predicted positions
  SolveLinks,       ///< distance constraints, every iteration
  SolveTetElasticity, ///< continuum tets (deviatoric + hydrostatic constraints), every iteration
  SolveVolumes,     ///< tet volume constraints, every iteration
  SolveAttachments, ///< soft pins, every iteration
  SolveContacts,    ///< detected contacts as inequality constraints, every iteration
  Residual,         ///< constraint residual after each iteration (tolerance or convergence output)
  UpdateVelocities, ///< v = (p - x) / h, x = p
  ContactResponse,  ///< restitution at the contacts, on the velocities (friction is in the solve)
  UpdateLinks,      ///< plasticity and breaking of links
  // Every method
  DivergenceCheck, ///< non-finite or exploded state (every few steps and at the last one)
  Transfers,       ///< GPU: host <-> device copies
  Count
};

/// Short lower-case name of a stage ("strain limit").
const char* stageName(Stage stage);

struct StageTiming
{
  Stage stage = Stage::Count;
  std::string label;    ///< the stage's name and what it runs here ("integrate: Verlet")
  double seconds = 0.0; ///< accumulated wall time since the simulation was made
};

class StepPlan
{
public:
  /// Appends a stage (in step order). `detail` says what it runs in this scene, e.g.
  /// "springs + volumes"; it becomes part of the label.
  void add(Stage stage, std::string detail = {});

  bool runs(Stage stage) const { return Runs[index(stage)]; }
  const std::vector<Stage>& stages() const { return Order; }
  std::string label(Stage stage) const;

  /// The timer slot of a stage (ScopedStageTimer adds to it).
  double& seconds(Stage stage) { return Seconds[index(stage)]; }
  double seconds(Stage stage) const { return Seconds[index(stage)]; }

  /// The planned stages in order with their labels and times.
  std::vector<StageTiming> timings() const;
  /// The labels in order ("forces: springs", "integrate: Euler-Cromer", ...).
  std::vector<std::string> labels() const;

private:
  static std::size_t index(Stage stage) { return static_cast<std::size_t>(stage); }
  static constexpr std::size_t kCount = static_cast<std::size_t>(Stage::Count);

  std::vector<Stage> Order;
  std::array<bool, kCount> Runs{};
  std::array<double, kCount> Seconds{};
  std::array<std::string, kCount> Details{};
};

} // namespace softbody
