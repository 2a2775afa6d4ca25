// The mass-spring body on the GPU: its buffers (constants uploaded once, state kept between
// steps) and the step as a fixed sequence of kernels in core's stage order. Everything here
// runs on the GL thread with the context current.
#pragma once

#include "condition_buffers.h"
#include "mass_spring_kernels.h"
#include "stage_clock.h"
#include "storage_buffer.h"

#include "softbody/common/step_plan.h"
#include "softbody/gpu/mass_spring_gpu_simulation.h" // DivergenceProbe
#include "softbody/massspring/mass_spring_setup.h"
#include "softbody/massspring/tet_body_contacts.h"

#include <initializer_list>
#include <utility>
#include <vector>

namespace softbody::gpu
{

class MassSpringDevice
{
public:
  /// Uploads the body's constants and its rest state. Throws GpuUnavailableError when a
  /// kernel does not compile or a buffer does not fit.
  /// `plan` (core's planMassSpring) says which stages step() runs; `floor` is the floor's
  /// contact as the CPU's detector has it (used when the plan has the floor).
  MassSpringDevice(const MassSpringSetup& setup, const StepPlan& plan, const FloorContact& floor);

  void uploadState(const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities);
  void downloadState(std::vector<Vec3>& positions, std::vector<Vec3>& velocities) const;

  /// One step of size h from time t: integrate (forces and loads inside), hold the held
  /// points, strain limit, floor. `kick` is the velocity kick of Verlet (ignored by the
  /// other integrators).
  void step(double h, double kick, double t);
  /// The conditions got new values (a widget moved): they are uploaded before the next step.
  void conditionValuesChanged() { Held.valuesChanged(); }
  DivergenceProbe probeDivergence();

  /// GPU time per Stage so far, indexed by the enum (waits for the GPU to finish what was timed).
  const std::vector<double>& stageSeconds();

private:
  /// Accelerations at the state (x, v) and time t into Accelerations.
  void computeAccelerations(const StorageBuffer& x, const StorageBuffer& v, double t);
  /// The loads and held components' buffers bound to a gather kernel, and its uniforms.
  void bindConditions(const ComputeProgram& gather);
  void holdPoints(double t);
  void springNetworkAccelerations(const StorageBuffer& x, const StorageBuffer& v);
  void tetElasticAccelerations(const StorageBuffer& x, const StorageBuffer& v);
  void integrate(double h, double kick, double t);
  /// `program` made current with `buffers` bound to its storage blocks by name; set its
  /// uniforms, then dispatch.
  static const ComputeProgram& bound(const ComputeProgram& program,
    std::initializer_list<std::pair<const char*, const StorageBuffer*>> buffers);
  /// One integrator update kernel over the vertices: it reads the state and the accelerations
  /// (bound here) plus `extraBuffers`, with its step-size uniforms.
  void runUpdate(const ComputeProgram& program,
    std::initializer_list<std::pair<const char*, const StorageBuffer*>> extraBuffers,
    std::initializer_list<std::pair<const char*, double>> stepSizes);
  void limitStrain(double h);
  void resolveFloor(double h);

  SceneSettings Scene;
  FloorContact Floor;
  bool LimitsStrain = false; ///< the plan's decisions, taken once
  bool HasFloor = false;
  std::size_t VertexCount = 0;
  std::size_t EdgeCount = 0;
  std::size_t TetCount = 0;
  bool HasVolumeTerm = false;
  bool Continuum = false; ///< finite-element tets instead of the network
  bool Corotated = false; ///< the tets' model: Corotated, else Stable Neo-Hookean

  MassSpringKernels Kernels;
  ConditionBuffers Held; ///< loads, held components and their targets
  StageClock Clock;

  // Constants (uploaded once).
  StorageBuffer Edges;            ///< ivec2 per edge
  StorageBuffer EdgeConstants;    ///< (l0, k, k_d, 0) per edge
  StorageBuffer Tets;             ///< ivec4 per tet
  StorageBuffer TetConstants;     ///< (V0, k', k_d', 0) per tet
  StorageBuffer VertexEdges;      ///< CSR [offsets | signed edge items]
  StorageBuffer VertexTetCorners; ///< CSR [offsets | 4 tet + corner]
  StorageBuffer InverseMasses;    ///< double per vertex
  StorageBuffer ShapeGradients;   ///< 4 dvec4 per tet (continuum)
  StorageBuffer TetLaws;          ///< 2 dvec4 per tet (continuum; see tet_elastic_forces.comp)
  // State and work arrays (dvec4 per vertex or element).
  StorageBuffer Positions;
  StorageBuffer Velocities;
  StorageBuffer StartPositions; ///< at the step's start, for the floor's contacts (swept, friction)
  StorageBuffer MidPositions;
  StorageBuffer MidVelocities;
  StorageBuffer Accelerations;
  StorageBuffer SpringForces;
  StorageBuffer CornerForces; ///< 4 dvec4 per tet (continuum)
  StorageBuffer TetScales; ///< double per tet
  StorageBuffer EdgeCorrections;
  StorageBuffer Partials; ///< one dvec4 per work group of the divergence check
  std::vector<double> PartialsHost;
};

} // namespace softbody::gpu
