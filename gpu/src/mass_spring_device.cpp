#include "mass_spring_device.h"

#include "softbody/material/isotropic_elasticity.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace softbody::gpu
{
namespace
{

/// Vec3 (3 packed doubles) -> dvec4 with w = 0: std430 arrays of dvec3 have a 32-byte stride.
std::vector<double> toDvec4(const std::vector<Vec3>& values)
{
  std::vector<double> packed(4 * values.size(), 0.0);
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    packed[4 * i + 0] = values[i].x();
    packed[4 * i + 1] = values[i].y();
    packed[4 * i + 2] = values[i].z();
  }
  return packed;
}

void fromDvec4(const std::vector<double>& packed, std::vector<Vec3>& values)
{
  values.resize(packed.size() / 4);
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    values[i] = Vec3(packed[4 * i + 0], packed[4 * i + 1], packed[4 * i + 2]);
  }
}

/// Per-element constants as dvec4 (a, b, c, 0).
std::vector<double> packConstants(
  const std::vector<double>& a, const std::vector<double>& b, const std::vector<double>& c)
{
  std::vector<double> packed(4 * a.size(), 0.0);
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    packed[4 * i + 0] = a[i];
    packed[4 * i + 1] = b[i];
    packed[4 * i + 2] = c[i];
  }
  return packed;
}

/// [offsets | items] in one array: a kernel may bind only 8 storage blocks (GL 4.3 minimum).
std::vector<std::int32_t> flattenCsr(const Csr& csr)
{
  std::vector<std::int32_t> flat(csr.offsets);
  flat.insert(flat.end(), csr.items.begin(), csr.items.end());
  return flat;
}

/// Vertex -> edge incidence with the end encoded in the sign: e when the vertex is the edge's
/// end a, ~e when it is end b (the gather needs the sign only).
std::vector<std::int32_t> signedVertexEdges(const Topology& topology)
{
  std::vector<std::int32_t> flat = flattenCsr(topology.vertexEdges);
  const std::size_t itemsStart = topology.vertexEdges.offsets.size();
  for (std::size_t i = 0; i < topology.vertexCount; ++i)
  {
    for (std::int32_t k = topology.vertexEdges.offsets[i]; k < topology.vertexEdges.offsets[i + 1]; ++k)
    {
      std::int32_t& item = flat[itemsStart + static_cast<std::size_t>(k)];
      if (topology.edges[static_cast<std::size_t>(item)].a != static_cast<std::int32_t>(i))
      {
        item = ~item;
      }
    }
  }
  return flat;
}

/// The continuum's per-tet constants as tet_elastic_forces.comp reads them: 4 shape gradients,
/// then (V0, law mu, law lambda, alpha) and (linear mu, linear lambda, damping time, 0);
/// alpha is Stable Neo-Hookean's rest shift of J (0 for Corotated, which has none).
std::vector<double> packShapeGradients(const TetElasticConstants& c)
{
  std::vector<double> packed(16 * c.shapeGradients.size(), 0.0);
  for (std::size_t t = 0; t < c.shapeGradients.size(); ++t)
  {
    for (std::size_t k = 0; k < 4; ++k)
    {
      for (int d = 0; d < 3; ++d)
      {
        packed[16 * t + 4 * k + static_cast<std::size_t>(d)] = c.shapeGradients[t][k](d);
      }
    }
  }
  return packed;
}

std::vector<double> packTetLaws(const TetElasticConstants& c, MaterialModel model)
{
  std::vector<double> packed(8 * c.restVolume.size(), 0.0);
  for (std::size_t t = 0; t < c.restVolume.size(); ++t)
  {
    double* law = &packed[8 * t];
    law[0] = c.restVolume[t];
    law[1] = c.law[t].mu;
    law[2] = c.law[t].lambda;
    law[3] = model == MaterialModel::StableNeoHookean ? StableNeoHookeanLaw::alpha(c.law[t]) : 0.0;
    law[4] = c.linear[t].mu;
    law[5] = c.linear[t].lambda;
    law[6] = c.damped ? c.dampingTime[t] : 0.0;
  }
  return packed;
}

StorageBuffer vectorBuffer(const char* name, std::size_t count)
{
  return StorageBuffer(name, 4 * sizeof(double) * count);
}

void toArray(const Vec3& v, double (&out)[3])
{
  out[0] = v.x();
  out[1] = v.y();
  out[2] = v.z();
}

} // namespace

MassSpringDevice::MassSpringDevice(
  const MassSpringSetup& setup, const StepPlan& plan, const FloorContact& floor)
  : Scene(setup.scene)
  , Floor(floor)
  , LimitsStrain(plan.runs(Stage::StrainLimit))
  , HasFloor(plan.runs(Stage::Floor))
  , VertexCount(setup.topology.vertexCount)
  , EdgeCount(setup.topology.edges.size())
  , TetCount(setup.topology.tets.size())
  , HasVolumeTerm(setup.constants.hasVolumeTerm)
  , Continuum(isContinuum(setup.model))
  , Corotated(setup.model == MaterialModel::Corotated)
  , Held(setup.conditions, setup.mesh.points)
  , Clock(static_cast<std::size_t>(Stage::Count))
{
  static_assert(sizeof(Edge) == 2 * sizeof(std::int32_t), "Edge must be two packed int32 (ivec2)");
  static_assert(sizeof(Tet) == 4 * sizeof(std::int32_t), "Tet must be four packed int32 (ivec4)");
  const Topology& topology = setup.topology;
  const ElementConstants& c = setup.constants;
  Edges = StorageBuffer::fromVector("edges", topology.edges);
  EdgeConstants = StorageBuffer::fromVector(
    "edge constants", packConstants(c.restLength, c.springStiffness, c.springDamping));
  Tets = StorageBuffer::fromVector("tets", topology.tets);
  TetConstants = StorageBuffer::fromVector(
    "tet constants", packConstants(c.restVolume, c.volumeStiffness, c.volumeDamping));
  VertexEdges = StorageBuffer::fromVector("vertex edges", signedVertexEdges(topology));
  VertexTetCorners = StorageBuffer::fromVector("vertex tet corners", flattenCsr(topology.vertexTetCorners));
  InverseMasses = StorageBuffer::fromVector("inverse masses", setup.masses.inverseMass);
  if (Continuum)
  {
    ShapeGradients = StorageBuffer::fromVector("shape gradients", packShapeGradients(setup.tetConstants));
    TetLaws = StorageBuffer::fromVector("tet materials", packTetLaws(setup.tetConstants, setup.model));
    CornerForces = vectorBuffer("tet corner forces", 4 * TetCount);
  }

  Positions = vectorBuffer("positions", VertexCount);
  Velocities = vectorBuffer("velocities", VertexCount);
  Accelerations = vectorBuffer("accelerations", VertexCount);
  if (HasFloor)
  {
    StartPositions = vectorBuffer("step start positions", VertexCount);
  }
  if (Scene.integrator == Integrator::Midpoint)
  {
    MidPositions = vectorBuffer("midpoint positions", VertexCount);
    MidVelocities = vectorBuffer("midpoint velocities", VertexCount);
  }
  // The network's force buffers only where the network makes the forces (the springs' rest
  // lengths stay for the strain limiter and the divergence check either way).
  SpringForces = vectorBuffer("spring forces", Continuum ? 0 : EdgeCount);
  TetScales = StorageBuffer("tet scales", sizeof(double) * (!Continuum && HasVolumeTerm ? TetCount : 0));
  if (LimitsStrain)
  {
    EdgeCorrections = vectorBuffer("edge corrections", EdgeCount);
  }
  const std::size_t groups = ComputeProgram::groupCount(std::max(EdgeCount, VertexCount));
  Partials = vectorBuffer("divergence partials", groups);
  PartialsHost.resize(4 * groups);
}

void MassSpringDevice::uploadState(
  const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities)
{
  const std::vector<double> x = toDvec4(positions);
  const std::vector<double> v = toDvec4(velocities);
  Positions.upload(x.data(), x.size() * sizeof(double));
  Velocities.upload(v.data(), v.size() * sizeof(double));
}

void MassSpringDevice::downloadState(
  std::vector<Vec3>& positions, std::vector<Vec3>& velocities) const
{
  std::vector<double> packed(4 * VertexCount);
  Positions.download(packed.data(), packed.size() * sizeof(double));
  fromDvec4(packed, positions);
  Velocities.download(packed.data(), packed.size() * sizeof(double));
  fromDvec4(packed, velocities);
}

void MassSpringDevice::computeAccelerations(const StorageBuffer& x, const StorageBuffer& v, double t)
{
  Held.updateLoads(t); // before the clock: a host computation and an upload, not GPU work
  Clock.begin(static_cast<std::size_t>(Stage::Forces));
  if (Continuum)
  {
    tetElasticAccelerations(x, v);
  }
  else
  {
    springNetworkAccelerations(x, v);
  }
  Clock.end();
}

const ComputeProgram& MassSpringDevice::bound(const ComputeProgram& program,
  std::initializer_list<std::pair<const char*, const StorageBuffer*>> buffers)
{
  program.use();
  for (const auto& [block, buffer] : buffers)
  {
    program.bind(block, *buffer);
  }
  return program;
}

void MassSpringDevice::tetElasticAccelerations(const StorageBuffer& x, const StorageBuffer& v)
{
  const ComputeProgram& stress = bound(Kernels.tetElasticForces,
    { { "Tets", &Tets }, { "ShapeGradients", &ShapeGradients }, { "TetLaws", &TetLaws },
      { "InPositions", &x }, { "InVelocities", &v }, { "CornerForces", &CornerForces } });
  stress.set("corotated", Corotated);
  stress.dispatch(TetCount);

  double gravity[3];
  toArray(Scene.gravity, gravity);
  const ComputeProgram& gather = bound(Kernels.gatherCornerForces,
    { { "CornerForces", &CornerForces }, { "VertexTetCorners", &VertexTetCorners },
      { "InverseMasses", &InverseMasses }, { "Accelerations", &Accelerations } });
  gather.set("gravity", gravity);
  bindConditions(gather);
  gather.dispatch(VertexCount);
}

void MassSpringDevice::bindConditions(const ComputeProgram& gather)
{
  gather.bind("Loads", Held.loads());
  gather.bind("HeldAxes", Held.heldAxes());
  gather.set("hasLoads", Held.hasLoads());
  gather.set("hasHeldAxes", Held.hasHeldPoints());
}

void MassSpringDevice::holdPoints(double t)
{
  Held.updateHeldTargets(t);
  Clock.begin(static_cast<std::size_t>(Stage::Integrate));
  bound(Kernels.holdPoints,
    { { "HeldPoints", &Held.heldPoints() }, { "HeldAxes", &Held.heldAxes() },
      { "HeldTargets", &Held.heldTargets() }, { "Positions", &Positions }, { "Velocities", &Velocities } })
    .dispatch(Held.heldPointCount());
  Clock.end();
}

void MassSpringDevice::springNetworkAccelerations(const StorageBuffer& x, const StorageBuffer& v)
{
  bound(Kernels.springForces,
    { { "Edges", &Edges }, { "EdgeConstants", &EdgeConstants }, { "InPositions", &x },
      { "InVelocities", &v }, { "SpringForces", &SpringForces } })
    .dispatch(EdgeCount);
  if (HasVolumeTerm)
  {
    bound(Kernels.volumeForces,
      { { "Tets", &Tets }, { "TetConstants", &TetConstants }, { "InPositions", &x },
        { "InVelocities", &v }, { "TetScales", &TetScales } })
      .dispatch(TetCount);
  }

  double gravity[3];
  toArray(Scene.gravity, gravity);
  const ComputeProgram& gather = bound(Kernels.gatherAccelerations,
    { { "SpringForces", &SpringForces }, { "VertexEdges", &VertexEdges }, { "TetScales", &TetScales },
      { "VertexTetCorners", &VertexTetCorners }, { "Tets", &Tets }, { "InPositions", &x },
      { "InverseMasses", &InverseMasses }, { "Accelerations", &Accelerations } });
  gather.set("hasVolumeTerm", HasVolumeTerm);
  gather.set("gravity", gravity);
  bindConditions(gather);
  gather.dispatch(VertexCount);
}

void MassSpringDevice::runUpdate(const ComputeProgram& program,
  std::initializer_list<std::pair<const char*, const StorageBuffer*>> extraBuffers,
  std::initializer_list<std::pair<const char*, double>> stepSizes)
{
  bound(program, { { "Positions", &Positions }, { "Velocities", &Velocities }, { "Accelerations", &Accelerations } });
  for (const auto& [block, buffer] : extraBuffers)
  {
    program.bind(block, *buffer);
  }
  for (const auto& [uniform, value] : stepSizes)
  {
    program.set(uniform, value);
  }
  Clock.begin(static_cast<std::size_t>(Stage::Integrate));
  program.dispatch(VertexCount);
  Clock.end();
}

void MassSpringDevice::integrate(double h, double kick, double t)
{
  // The integrators of core's explicit_integrators.cpp; force evaluations are timed as
  // "forces", the update kernels as "integrate".
  computeAccelerations(Positions, Velocities, t);
  switch (Scene.integrator)
  {
    case Integrator::Euler:
      runUpdate(Kernels.eulerStep, {}, { { "h", h } });
      break;
    case Integrator::Midpoint:
      runUpdate(Kernels.midpointPredict,
        { { "MidPositions", &MidPositions }, { "MidVelocities", &MidVelocities } },
        { { "halfH", 0.5 * h } });
      computeAccelerations(MidPositions, MidVelocities, t + 0.5 * h);
      runUpdate(Kernels.midpointStep, { { "MidVelocities", &MidVelocities } }, { { "h", h } });
      break;
    case Integrator::Verlet:
    case Integrator::EulerCromer:
      // Euler-Cromer is the kick-drift with a kick of h; Verlet kicks by the mean step.
      runUpdate(Kernels.kickDrift, {},
        { { "kick", Scene.integrator == Integrator::Verlet ? kick : h }, { "h", h } });
      break;
    case Integrator::ImplicitEuler:
    case Integrator::ProjectiveDynamics:
    case Integrator::Static:
    case Integrator::Bdf2:
    case Integrator::VertexBlockDescent:
      // Refused in tryCreateGpuMassSpring (the filter then runs them on the CPU).
      throw std::logic_error("the GPU stepper has no implicit integrator");
  }
}

void MassSpringDevice::limitStrain(double h)
{
  Clock.begin(static_cast<std::size_t>(Stage::StrainLimit));
  const ComputeProgram& corrections = Kernels.strainCorrections;
  const ComputeProgram& apply = Kernels.strainApply;
  for (int iteration = 0; iteration < Scene.strainLimitIterations; ++iteration)
  {
    corrections.use();
    corrections.bind("Edges", Edges);
    corrections.bind("EdgeConstants", EdgeConstants);
    corrections.bind("InverseMasses", InverseMasses);
    corrections.bind("Positions", Positions);
    corrections.bind("EdgeCorrections", EdgeCorrections);
    corrections.set("maxStretch", Scene.strainLimit);
    corrections.dispatch(EdgeCount);

    apply.use();
    apply.bind("VertexEdges", VertexEdges);
    apply.bind("EdgeCorrections", EdgeCorrections);
    apply.bind("InverseMasses", InverseMasses);
    apply.bind("Positions", Positions);
    apply.bind("Velocities", Velocities);
    // Verlet's velocity is the position difference of the last step: a moved point moves it.
    apply.set("adjustVelocities", factsOf(Scene.integrator).velocityFromPositions);
    apply.set("h", h);
    apply.dispatch(VertexCount);
  }
  Clock.end();
}

void MassSpringDevice::resolveFloor(double h)
{
  Clock.begin(static_cast<std::size_t>(Stage::Floor));
  const ComputeProgram& floor = Kernels.floorContacts;
  floor.use();
  floor.bind("InverseMasses", InverseMasses);
  floor.bind("StartPositions", StartPositions);
  floor.bind("Positions", Positions);
  floor.bind("Velocities", Velocities);
  double origin[3], normal[3];
  toArray(Floor.plane.origin, origin);
  toArray(Floor.plane.normal, normal);
  floor.set("floorOrigin", origin);
  floor.set("floorNormal", normal);
  floor.set("thickness", Floor.thickness);
  floor.set("h", h);
  floor.set("staticFriction", Scene.collisions.staticFriction);
  floor.set("dynamicFriction", Scene.collisions.dynamicFriction);
  floor.set("restitution", Scene.collisions.restitution);
  floor.dispatch(VertexCount);
  Clock.end();
}

void MassSpringDevice::step(double h, double kick, double t)
{
  // Core's stage order (MassSpringSimulation::takeStep).
  if (HasFloor)
  {
    StartPositions.copyFrom(Positions); // the contacts are swept from the step's start
  }
  integrate(h, kick, t);
  if (Held.hasHeldPoints())
  {
    holdPoints(t + h); // core's state.time after the step: t + h, summed the same way
  }
  if (LimitsStrain)
  {
    limitStrain(h);
  }
  if (HasFloor)
  {
    resolveFloor(h);
  }
}

DivergenceProbe MassSpringDevice::probeDivergence()
{
  Clock.begin(static_cast<std::size_t>(Stage::DivergenceCheck));
  const ComputeProgram& probe = Kernels.divergencePartials;
  probe.use();
  probe.bind("Edges", Edges);
  probe.bind("EdgeConstants", EdgeConstants);
  probe.bind("Positions", Positions);
  probe.bind("Velocities", Velocities);
  probe.bind("Partials", Partials);
  probe.set("edgeCount", static_cast<unsigned>(EdgeCount));
  probe.set("vertexCount", static_cast<unsigned>(VertexCount));
  probe.dispatch(std::max(EdgeCount, VertexCount));
  Clock.end();
  Partials.download(PartialsHost.data(), PartialsHost.size() * sizeof(double));
  Clock.collect(); // the GPU is idle now: reading the timers costs nothing

  DivergenceProbe result;
  bool stretchIsNan = false;
  for (std::size_t g = 0; g < PartialsHost.size() / 4; ++g)
  {
    result.maxStretch = std::max(result.maxStretch, PartialsHost[4 * g + 0]);
    stretchIsNan = stretchIsNan || PartialsHost[4 * g + 1] != 0.0;
    result.finiteVelocities = result.finiteVelocities && PartialsHost[4 * g + 2] == 0.0;
  }
  if (stretchIsNan)
  {
    result.maxStretch = std::numeric_limits<double>::quiet_NaN();
  }
  return result;
}

const std::vector<double>& MassSpringDevice::stageSeconds()
{
  Clock.collect();
  return Clock.seconds();
}

} // namespace softbody::gpu
