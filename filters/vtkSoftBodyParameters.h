/**
 * @file   vtkSoftBodyParameters.h
 * @brief  Every property of the Soft Body filter as the user set it, with its default, and the
 *         enumerations the integer properties take.
 *
 * Setters never clamp: an out-of-range value is kept as typed and refused by core (or by
 * vtkSoftBodySettings, which turns this struct into core settings) quoting it. Mesh Quality keeps
 * the same struct for the properties it shares with the filter. vtkSoftBodyFilter exposes it as
 * vtkSoftBodyFilter::Parameters and the enumerators as vtkSoftBodyFilter::MASS_SPRING etc.
 */
#ifndef vtkSoftBodyParameters_h
#define vtkSoftBodyParameters_h

#include "vtkType.h" // for vtkTypeBool

#include <string> // for std::string

struct vtkSoftBodyParameters
{
  enum MethodType
  {
    MASS_SPRING = 0,
    PBD = 1,
    XPBD = 2,
    METHOD_AUTOMATIC = 3 ///< Mass-Spring for tets, XPBD for linked particles (vtkSoftBodyMethodChoice)
  };
  enum XPBDMaterialType
  {
    XPBD_COMPLIANCES = 0,    ///< the XPBD*Compliance properties, uniform per constraint type
    XPBD_YOUNGS_MODULUS = 1  ///< per-element compliances from YoungsModulus and PoissonRatio
  };
  enum SolverType
  {
    GAUSS_SEIDEL = 0,
    JACOBI = 1,
    PARALLEL_GAUSS_SEIDEL = 2
  };
  enum TimeStepModeType
  {
    FIXED_STEP = 0,
    ERROR_CONTROLLED = 1
  };
  enum IntegratorType
  {
    EULER = 0,
    MIDPOINT = 1,
    VERLET = 2,
    EULER_CROMER = 3,
    IMPLICIT_EULER = 4,
    PROJECTIVE_DYNAMICS = 5,
    STATIC = 6,
    BDF2 = 7,
    VERTEX_BLOCK_DESCENT = 8
  };
  enum MaterialModelType
  {
    SPRING_NETWORK = 0,
    COROTATED = 1,
    STABLE_NEO_HOOKEAN = 2
  };
  enum MaterialModeType
  {
    PHYSICAL = 0,
    RAW_CONSTANTS = 1
  };
  enum VolumetricFormulationType
  {
    PER_TET = 0,      ///< each tet holds its own volume (linear tets: lock as nu nears 0.5)
    NODAL_AVERAGE = 1 ///< the volume term averaged at the points: no volumetric locking
  };
  enum FloorPlacementType
  {
    FLOOR_AUTOMATIC = 0,           ///< through FloorOrigin, or under a body that starts below it
    FLOOR_UNDER_THE_BODY = 1,      ///< through the body's lowest point along FloorNormal
    FLOOR_THROUGH_FLOOR_ORIGIN = 2 ///< through FloorOrigin; a body below it is lifted onto it
  };
  enum MassDistributionType
  {
    AVERAGE_INCIDENT_VOLUME = 0,
    LUMPED_VOLUME = 1
  };
  enum InvertedTetsType
  {
    REORIENT = 0,
    REFUSE = 1
  };
  enum DeviceType
  {
    DEVICE_CPU = 0,
    DEVICE_GPU_EGL = 1
  };
  enum CollisionsType
  {
    COLLISIONS_OFF = 0,            ///< nothing, not even the floor
    COLLISIONS_OBSTACLES = 1,      ///< the floor and the Obstacles input (default)
    COLLISIONS_BODIES = 2,         ///< + the input's connected bodies against each other
    COLLISIONS_BODIES_AND_SELF = 3 ///< + each body against itself
  };
  enum BroadPhaseType
  {
    BROAD_PHASE_AUTOMATIC = 0,
    BROAD_PHASE_BRUTE_FORCE = 1,
    BROAD_PHASE_UNIFORM_GRID = 2,
    BROAD_PHASE_OCTREE = 3
  };

  int Method = METHOD_AUTOMATIC;
  int Device = DEVICE_CPU;
  int Integrator = EULER_CROMER;
  double TimeStep = 0.0;
  int TimeStepMode = FIXED_STEP;
  double ErrorTolerance = 1.0e-4;
  double ImplicitTolerance = 1.0e-3;
  int ImplicitMaxIterations = 100;
  double EndTime = 3.0;
  double FrameInterval = 0.04;
  double Gravity[3] = { 0.0, 0.0, -9.81 };
  vtkTypeBool Floor = 1;
  int FloorPlacement = FLOOR_AUTOMATIC;
  double FloorOrigin[3] = { 0.0, 0.0, 0.0 };
  double FloorNormal[3] = { 0.0, 0.0, 1.0 };
  std::string PinnedPointsArray;
  double InitialVelocity[3] = { 0.0, 0.0, 0.0 };
  double InitialAngularVelocity[3] = { 0.0, 0.0, 0.0 };
  std::string InitialVelocityArray;
  std::string InitialDisplacementArray;
  int MaterialModel = SPRING_NETWORK;
  int VolumetricFormulation = PER_TET;
  int MaterialMode = PHYSICAL;
  double YoungsModulus = 1.0e5;
  double PoissonRatio = 0.3;
  double Density = 1100.0;
  double DampingTime = 2.0e-3;
  std::string YoungsModulusArray;
  std::string PoissonRatioArray;
  std::string DensityArray;
  // Raw-mode defaults: vtkSoftBodySettings::DefaultParameters sets them from core's
  // softbody::RawConstants.
  double DistanceStiffness = 0.0;
  double DistanceDamping = 0.0;
  double VolumeStiffness = 0.0;
  double VolumeDamping = 0.0;
  double TotalMass = 0.0;
  int MassDistribution = AVERAGE_INCIDENT_VOLUME;
  double MaxInverseMass = 0.0;
  double StrainLimit = 0.0;
  int StrainLimitIterations = 4;
  int InvertedTets = REORIENT;
  int CacheMemoryLimit = 512;
  int Solver = GAUSS_SEIDEL;
  int Iterations = 10;
  double ResidualTolerance = 0.0;
  double Relaxation = 1.0;
  int Substeps = 1;
  double PBDLinkStiffness = 1.0;
  double PBDVolumeStiffness = 1.0;
  double PBDPinStiffness = 1.0;
  double XPBDLinkCompliance = 1.0e-4;
  double XPBDVolumeCompliance = 1.0e-10;
  double XPBDPinCompliance = 0.0;
  int XPBDMaterial = XPBD_COMPLIANCES;
  double BreakingStrain = 0.0;
  double PlasticYield = 0.0;
  double PlasticCreep = 0.0;
  int Collisions = COLLISIONS_OBSTACLES;
  int BroadPhase = BROAD_PHASE_AUTOMATIC;
  double CollisionMargin = 0.0;
  double StaticFriction = 0.3;
  double DynamicFriction = 0.3;
  double Restitution = 0.0;
  double VelocityDamping = 0.0;
};

#endif
