#include "vtkSoftBodySettings.h"

#include "vtkSoftBodyInputConversion.h"

#include "softbody/common/errors.h"
#include "softbody/common/validation.h"

namespace
{
softbody::Vec3 ToVec3(const double v[3])
{
  return { v[0], v[1], v[2] };
}

/// The value of an enumeration property, refused when it is not one of `count` choices.
int Choice(const char* name, int value, int count, const char* choices)
{
  if (value < 0 || value >= count)
  {
    softbody::check::badChoice(name, value, choices);
  }
  return value;
}

/// "0 (Spring Network), 1 (Corotated), ...": the refusal's list, from core's own names.
std::string MaterialModelChoices()
{
  std::string choices;
  for (int m = 0; m < int(softbody::MaterialModel::Count); ++m)
  {
    choices += (m > 0 ? ", " : "") + std::to_string(m) + " (" +
      softbody::materialModelName(static_cast<softbody::MaterialModel>(m)) + ")";
  }
  return choices;
}

softbody::MassDistribution CoreMassDistribution(int value)
{
  return Choice("MassDistribution", value, 2, "0 (average incident volume), 1 (lumped volume)") ==
      vtkSoftBodyFilter::LUMPED_VOLUME
    ? softbody::MassDistribution::LumpedVolume
    : softbody::MassDistribution::AverageIncidentVolume;
}

softbody::VolumetricFormulation CoreVolumetricFormulation(int value)
{
  return Choice("VolumetricFormulation", value, 2, "0 (per tet), 1 (nodal average)") ==
      vtkSoftBodyFilter::NODAL_AVERAGE
    ? softbody::VolumetricFormulation::NodalAverage
    : softbody::VolumetricFormulation::PerTet;
}

softbody::InvertedTetPolicy CoreInvertedTets(int value)
{
  return Choice("InvertedTets", value, 2, "0 (reorient), 1 (refuse)") == vtkSoftBodyFilter::REFUSE
    ? softbody::InvertedTetPolicy::Refuse
    : softbody::InvertedTetPolicy::Reorient;
}

softbody::CollisionMode CoreCollisionMode(int value)
{
  switch (Choice("Collisions", value, 4,
    "0 (Off), 1 (Obstacles), 2 (Obstacles + Bodies), 3 (Obstacles + Bodies + Self)"))
  {
    case vtkSoftBodyFilter::COLLISIONS_OFF:
      return softbody::CollisionMode::Off;
    case vtkSoftBodyFilter::COLLISIONS_BODIES:
      return softbody::CollisionMode::ObstaclesAndBodies;
    case vtkSoftBodyFilter::COLLISIONS_BODIES_AND_SELF:
      return softbody::CollisionMode::ObstaclesBodiesAndSelf;
    default:
      return softbody::CollisionMode::Obstacles;
  }
}

softbody::BroadPhase CoreBroadPhase(int value)
{
  switch (Choice("BroadPhase", value, 4, "0 (Automatic), 1 (Brute Force), 2 (Uniform Grid), 3 (Octree)"))
  {
    case vtkSoftBodyFilter::BROAD_PHASE_BRUTE_FORCE:
      return softbody::BroadPhase::BruteForce;
    case vtkSoftBodyFilter::BROAD_PHASE_UNIFORM_GRID:
      return softbody::BroadPhase::UniformGrid;
    case vtkSoftBodyFilter::BROAD_PHASE_OCTREE:
      return softbody::BroadPhase::Octree;
    default:
      return softbody::BroadPhase::Automatic;
  }
}

void ConvertMassSpring(const vtkSoftBodyFilter::Parameters& p, vtkSoftBodyCoreSettings& settings)
{
  softbody::SceneSettings& scene = settings.Scene;
  scene.integrator = vtkSoftBodySettings::Integrator(p.Integrator);
  scene.timeStep = p.TimeStep;
  if (softbody::isImplicit(scene.integrator))
  {
    scene.implicit.tolerance = p.ImplicitTolerance;
    scene.implicit.maxIterations = p.ImplicitMaxIterations;
  }
  static_cast<softbody::Scene&>(scene) = vtkSoftBodySettings::Scene(p);
  scene.strainLimit = p.StrainLimit;
  if (p.StrainLimit != 0.0)
  {
    scene.strainLimitIterations = p.StrainLimitIterations;
  }
  scene.invertedTets = CoreInvertedTets(p.InvertedTets);
  settings.Material = vtkSoftBodySettings::Material(p);
  settings.Device =
    Choice("Device", p.Device, 2, "0 (CPU), 1 (GPU (EGL))");
}

void ConvertPbd(const vtkSoftBodyFilter::Parameters& p, vtkSoftBodyCoreSettings& settings)
{
  softbody::PbdSettings& s = settings.Pbd;
  const bool xpbd = p.Method == vtkSoftBodyFilter::XPBD;
  s.formulation = xpbd ? softbody::PbdFormulation::Xpbd : softbody::PbdFormulation::Pbd;
  switch (Choice("Solver", p.Solver, 3, "0 (Gauss-Seidel), 1 (Jacobi), 2 (parallel Gauss-Seidel)"))
  {
    case vtkSoftBodyFilter::JACOBI:
      s.solver = softbody::PbdSolver::Jacobi;
      break;
    case vtkSoftBodyFilter::PARALLEL_GAUSS_SEIDEL:
      s.solver = softbody::PbdSolver::ParallelGaussSeidel;
      break;
    default:
      s.solver = softbody::PbdSolver::GaussSeidel;
  }
  if (p.Integrator != vtkSoftBodyFilter::EULER_CROMER && p.Integrator != vtkSoftBodyFilter::VERLET)
  {
    throw softbody::InvalidInputError(std::string("PBD and XPBD predict positions with "
                                                  "Euler-Cromer (3) or Verlet (2); Integrator is ") +
      std::to_string(p.Integrator) + " (" +
      softbody::integratorName(vtkSoftBodySettings::Integrator(p.Integrator)) +
      "). Choose one of those two.");
  }
  const softbody::MaterialModel model = vtkSoftBodySettings::Material(p).model;
  if (softbody::isContinuum(model) && !xpbd)
  {
    // PBD's stiffnesses in [0, 1] have no modulus for a continuum law's constraints.
    throw softbody::InvalidInputError("MaterialModel " + std::to_string(p.MaterialModel) + " (" +
      softbody::materialModelName(model) +
      ") runs under Method Mass-Spring and XPBD, whose stiffness comes from YoungsModulus and "
      "PoissonRatio; PBD's stiffnesses in [0, 1] have no modulus. Set Method to XPBD or "
      "Mass-Spring, or MaterialModel to Spring Network.");
  }
  s.prediction = p.Integrator == vtkSoftBodyFilter::VERLET ? softbody::PbdPrediction::Verlet
                                                           : softbody::PbdPrediction::SymplecticEuler;
  s.timeStep = p.TimeStep;
  s.substeps = p.Substeps;
  s.iterations = p.Iterations;
  s.residualTolerance = p.ResidualTolerance;
  s.relaxation = p.Relaxation;
  static_cast<softbody::Scene&>(s) = vtkSoftBodySettings::Scene(p);
  s.damping = p.VelocityDamping;
  softbody::MaterialSettings& material = settings.Material;
  material.physical.density = p.Density;
  material.massDistribution = CoreMassDistribution(p.MassDistribution);
  material.volumetric = CoreVolumetricFormulation(p.VolumetricFormulation);
  // Each formulation reads only its own constants: PBD stiffnesses, XPBD compliances (or
  // Young's modulus), so the other's properties do not invalidate the cache.
  if (xpbd)
  {
    s.links.compliance = p.XPBDLinkCompliance;
    s.volumes.compliance = p.XPBDVolumeCompliance;
    s.attachments.compliance = p.XPBDPinCompliance;
    // A continuum model's constraints always come from E and nu; XPBDMaterial chooses where
    // the Spring Network's come from.
    const bool fromModulus = Choice("XPBDMaterial", p.XPBDMaterial, 2,
                               "0 (compliances), 1 (Young's modulus)") == vtkSoftBodyFilter::XPBD_YOUNGS_MODULUS;
    if (fromModulus || softbody::isContinuum(model))
    {
      s.elasticFromMaterial = true;
      material.model = model;
      material.physical.youngsModulus = p.YoungsModulus;
      material.physical.poissonRatio = p.PoissonRatio;
    }
  }
  else
  {
    s.links.stiffness = p.PBDLinkStiffness;
    s.volumes.stiffness = p.PBDVolumeStiffness;
    s.attachments.stiffness = p.PBDPinStiffness;
  }
  s.breakingStrain = p.BreakingStrain;
  s.plasticYield = p.PlasticYield;
  if (p.PlasticYield > 0.0)
  {
    s.plasticCreep = p.PlasticCreep;
  }
  s.invertedTets = CoreInvertedTets(p.InvertedTets);
}
} // namespace

//------------------------------------------------------------------------------
// The Integrator property's values are core's enumeration (the XML lists them in this order).
static_assert(vtkSoftBodyFilter::EULER == int(softbody::Integrator::Euler) &&
    vtkSoftBodyFilter::MIDPOINT == int(softbody::Integrator::Midpoint) &&
    vtkSoftBodyFilter::VERLET == int(softbody::Integrator::Verlet) &&
    vtkSoftBodyFilter::EULER_CROMER == int(softbody::Integrator::EulerCromer) &&
    vtkSoftBodyFilter::IMPLICIT_EULER == int(softbody::Integrator::ImplicitEuler) &&
    vtkSoftBodyFilter::PROJECTIVE_DYNAMICS == int(softbody::Integrator::ProjectiveDynamics) &&
    vtkSoftBodyFilter::STATIC == int(softbody::Integrator::Static) &&
    vtkSoftBodyFilter::BDF2 == int(softbody::Integrator::Bdf2) &&
    vtkSoftBodyFilter::VERTEX_BLOCK_DESCENT == int(softbody::Integrator::VertexBlockDescent),
  "the Integrator property's values must be core's Integrator values");

softbody::Integrator vtkSoftBodySettings::Integrator(int integrator)
{
  const auto table = softbody::integratorTable();
  std::string choices;
  for (const softbody::IntegratorFacts& facts : table)
  {
    choices += (choices.empty() ? "" : ", ") + std::to_string(int(facts.integrator)) + " (" +
      facts.name + ")";
  }
  return static_cast<softbody::Integrator>(
    Choice("Integrator", integrator, static_cast<int>(table.size()), choices.c_str()));
}

//------------------------------------------------------------------------------
softbody::Scene vtkSoftBodySettings::Scene(const vtkSoftBodyFilter::Parameters& p)
{
  softbody::Scene scene;
  scene.gravity = ToVec3(p.Gravity);
  scene.collisions = vtkSoftBodySettings::Collisions(p);
  scene.floorEnabled = p.Floor != 0;
  if (scene.floorActive())
  {
    // Where it goes from FloorOrigin needs the body: the filter places it
    // (vtkSoftBodyFloorPlacement); the value is checked here with the others.
    Choice("FloorPlacement", p.FloorPlacement, 3,
      "0 (Automatic), 1 (Under the Body), 2 (Through Floor Origin)");
    scene.floor.origin = ToVec3(p.FloorOrigin);
    scene.floor.normal = ToVec3(p.FloorNormal);
  }
  else
  {
    // A floor nothing touches is not read: leaving it at its default keeps the cache when only
    // the Floor properties change.
    scene.floorEnabled = false;
  }
  if (Choice("TimeStepMode", p.TimeStepMode, 2, "0 (Fixed), 1 (Error-controlled)") ==
    vtkSoftBodyFilter::ERROR_CONTROLLED)
  {
    // Core refuses what cannot be error-controlled (PBD, the static solve), quoting the value.
    scene.stepControl = softbody::StepControl::ErrorControlled;
    scene.errorTolerance = p.ErrorTolerance;
  }
  return scene;
}

//------------------------------------------------------------------------------
softbody::CollisionSettings vtkSoftBodySettings::Collisions(const vtkSoftBodyFilter::Parameters& p)
{
  softbody::CollisionSettings collisions;
  collisions.mode = CoreCollisionMode(p.Collisions);
  if (!collisions.on())
  {
    return collisions; // nothing collides: the other values are not read (nor key the cache)
  }
  collisions.broadPhase = CoreBroadPhase(p.BroadPhase);
  collisions.margin = p.CollisionMargin;
  collisions.staticFriction = p.StaticFriction;
  collisions.dynamicFriction = p.DynamicFriction;
  collisions.restitution = p.Restitution;
  // Ranges are core's to refuse (CollisionDetector), quoting the value; the broad phase only
  // changes the cost, but it stays in the key so a benchmark run really uses the one asked for.
  return collisions;
}

//------------------------------------------------------------------------------
softbody::MaterialSettings vtkSoftBodySettings::Material(const vtkSoftBodyFilter::Parameters& p)
{
  softbody::MaterialSettings material;
  static_assert(vtkSoftBodyFilter::SPRING_NETWORK == int(softbody::MaterialModel::SpringNetwork) &&
      vtkSoftBodyFilter::COROTATED == int(softbody::MaterialModel::Corotated) &&
      vtkSoftBodyFilter::STABLE_NEO_HOOKEAN == int(softbody::MaterialModel::StableNeoHookean),
    "the MaterialModel property's values must be core's MaterialModel values");
  material.model = static_cast<softbody::MaterialModel>(Choice("MaterialModel", p.MaterialModel,
    int(softbody::MaterialModel::Count), MaterialModelChoices().c_str()));
  if (Choice("MaterialMode", p.MaterialMode, 2, "0 (physical), 1 (raw constants)") ==
    vtkSoftBodyFilter::RAW_CONSTANTS)
  {
    material.mode = softbody::MaterialMode::Raw;
    material.raw.distanceStiffness = p.DistanceStiffness;
    material.raw.distanceDamping = p.DistanceDamping;
    material.raw.volumeStiffness = p.VolumeStiffness;
    material.raw.volumeDamping = p.VolumeDamping;
    material.raw.totalMass = p.TotalMass;
  }
  else
  {
    material.mode = softbody::MaterialMode::Physical;
    material.physical.youngsModulus = p.YoungsModulus;
    material.physical.poissonRatio = p.PoissonRatio;
    material.physical.density = p.Density;
    material.physical.dampingTime = p.DampingTime;
  }
  material.massDistribution = CoreMassDistribution(p.MassDistribution);
  material.volumetric = CoreVolumetricFormulation(p.VolumetricFormulation);
  material.maxInverseMass = p.MaxInverseMass;
  return material;
}

//------------------------------------------------------------------------------
void vtkSoftBodySettings::ValidateTimes(const vtkSoftBodyFilter::Parameters& p)
{
  softbody::check::positive("EndTime", p.EndTime, "s");
  softbody::check::positive("FrameInterval", p.FrameInterval, "s");
  if (p.EndTime / p.FrameInterval > MaxFrames)
  {
    throw softbody::InvalidInputError("EndTime / FrameInterval = " +
      softbody::check::quote(p.EndTime) + " s / " + softbody::check::quote(p.FrameInterval) +
      " s gives more than " + softbody::check::quote(MaxFrames) +
      " frames; increase FrameInterval.");
  }
  softbody::check::atLeast("CacheMemoryLimit", p.CacheMemoryLimit, 0);
}

//------------------------------------------------------------------------------
vtkSoftBodyCoreSettings vtkSoftBodySettings::Convert(const vtkSoftBodyFilter::Parameters& p)
{
  ValidateTimes(p);
  vtkSoftBodyCoreSettings settings;
  // Automatic (3) is resolved from the input before this (vtkSoftBodyMethodChoice); it is
  // listed so that a refusal names every value the property takes.
  settings.Method = Choice("Method", p.Method, 3, "0 (Mass-Spring), 1 (PBD), 2 (XPBD), 3 (Automatic)");
  settings.FrameInterval = p.FrameInterval;
  settings.PinnedPointsArray =
    vtkSoftBodyInputConversion::IsNoArray(p.PinnedPointsArray) ? "" : p.PinnedPointsArray;
  const auto arrayName = [](const std::string& name) {
    return vtkSoftBodyInputConversion::IsNoArray(name) ? std::string() : name;
  };
  settings.Initial.velocity = ToVec3(p.InitialVelocity);
  settings.Initial.spin = ToVec3(p.InitialAngularVelocity);
  if (!settings.Initial.velocity.allFinite() || !settings.Initial.spin.allFinite())
  {
    throw softbody::InvalidInputError("InitialVelocity and InitialAngularVelocity must be finite, got (" +
      std::to_string(p.InitialVelocity[0]) + ", " + std::to_string(p.InitialVelocity[1]) + ", " +
      std::to_string(p.InitialVelocity[2]) + ") m/s and (" + std::to_string(p.InitialAngularVelocity[0]) +
      ", " + std::to_string(p.InitialAngularVelocity[1]) + ", " +
      std::to_string(p.InitialAngularVelocity[2]) + ") rad/s.");
  }
  settings.Initial.velocityArray = arrayName(p.InitialVelocityArray);
  settings.Initial.displacementArray = arrayName(p.InitialDisplacementArray);
  // Core checks each per-cell value, and refuses arrays the method would not read.
  settings.YoungsModulusArray = arrayName(p.YoungsModulusArray);
  settings.PoissonRatioArray = arrayName(p.PoissonRatioArray);
  settings.DensityArray = arrayName(p.DensityArray);
  if (settings.Method == vtkSoftBodyFilter::MASS_SPRING)
  {
    ConvertMassSpring(p, settings);
  }
  else
  {
    ConvertPbd(p, settings);
  }
  return settings;
}

//------------------------------------------------------------------------------
std::vector<std::string> vtkSoftBodySettings::Warnings(const vtkSoftBodyFilter::Parameters& p)
{
  std::vector<std::string> warnings;
  if (p.CacheMemoryLimit == 0)
  {
    warnings.push_back("CacheMemoryLimit is 0 MiB: only frame 0 is cached, so every time "
                       "request simulates again from the start or the last frame; set a budget "
                       "(default 512 MiB) to scrub and replay without simulating.");
  }
  if (p.Method != vtkSoftBodyFilter::MASS_SPRING && p.Device == vtkSoftBodyFilter::DEVICE_GPU_EGL)
  {
    warnings.push_back("Device GPU (EGL) runs Mass-Spring only; PBD and XPBD run on the CPU.");
  }
  return warnings;
}

//------------------------------------------------------------------------------
void vtkSoftBodySettings::PrintMaterial(
  ostream& os, vtkIndent indent, const vtkSoftBodyFilter::Parameters& p)
{
  os << indent << "MaterialModel: " << p.MaterialModel << "\n";
  os << indent << "VolumetricFormulation: " << p.VolumetricFormulation << "\n";
  os << indent << "YoungsModulusArray: " << p.YoungsModulusArray << "\n";
  os << indent << "PoissonRatioArray: " << p.PoissonRatioArray << "\n";
  os << indent << "DensityArray: " << p.DensityArray << "\n";
  os << indent << "MaterialMode: " << p.MaterialMode << "\n";
  os << indent << "YoungsModulus: " << p.YoungsModulus << "\n";
  os << indent << "PoissonRatio: " << p.PoissonRatio << "\n";
  os << indent << "Density: " << p.Density << "\n";
  os << indent << "DampingTime: " << p.DampingTime << "\n";
  os << indent << "DistanceStiffness: " << p.DistanceStiffness << "\n";
  os << indent << "DistanceDamping: " << p.DistanceDamping << "\n";
  os << indent << "VolumeStiffness: " << p.VolumeStiffness << "\n";
  os << indent << "VolumeDamping: " << p.VolumeDamping << "\n";
  os << indent << "TotalMass: " << p.TotalMass << "\n";
  os << indent << "MassDistribution: " << p.MassDistribution << "\n";
}

//------------------------------------------------------------------------------
vtkSoftBodyFilter::Parameters vtkSoftBodySettings::DefaultParameters()
{
  vtkSoftBodyFilter::Parameters p;
  // One source of truth for the raw-mode defaults: core's RawConstants.
  const softbody::RawConstants raw;
  p.DistanceStiffness = raw.distanceStiffness;
  p.DistanceDamping = raw.distanceDamping;
  p.VolumeStiffness = raw.volumeStiffness;
  p.VolumeDamping = raw.volumeDamping;
  p.TotalMass = raw.totalMass;
  return p;
}
