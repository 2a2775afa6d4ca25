/**
 * @class   vtkSoftBodyFilter
 * @brief   Simulates a mesh as a soft body (mass-spring, PBD or XPBD) and outputs it over time.
 *
 * The input is a vtkUnstructuredGrid at rest: tetrahedra for the mass-spring method; for PBD and
 * XPBD tetrahedra (edges and volumes) and line cells (distance links, e.g. from Soft Body
 * Cloth), other cells moving with their points. The filter is a time source: it advertises the times
 * 0, FrameInterval, 2 FrameInterval, ..., EndTime, and for a requested time it outputs
 *
 * - port 0 ("Mesh"): the input grid with its points moved, the input point and cell arrays passed
 *   through, point arrays "Velocity" [m/s] and "Displacement" [m], cell array "VolumeRatio"
 *   (current / rest volume) and field data "SimulationTime", "StepCount", "TimeStep",
 *   "StableTimeStep", "Integrator", "Plan", "StageSeconds", "Warnings", "TotalMass", "Device"
 *   (the device that ran the steps) and "GLRenderer" (the GPU's renderer; empty on the CPU); for
 *   PBD and XPBD also cell array "Broken" (broken links, and tets with a broken edge, which are
 *   hidden through vtkGhostType so the body visibly fragments) and field data "Iterations" and
 *   "Residual" of the frame's last step;
 * - port 1 ("Particles"): a vtkPolyData with one vertex per point and point arrays "Velocity" and
 *   "InverseMass";
 * - port 2 ("Convergence"): a vtkTable of the residual after each iteration of the frame's last
 *   (sub)step (PBD and XPBD; empty for mass-spring);
 * - port 3 ("Surface"): when a surface is connected to input port 1 (optional), that surface
 *   (same cells and arrays) moving with the body, normals recomputed: bound once to a Soft Body
 *   Voxelize lattice with trilinear weights or to a tet body with barycentric ones;
 * - port 4 ("Floor"): the floor plane as a square sized to the body (vtkSoftBodyFloorOutput),
 *   empty when Floor is off.
 *
 * "Velocity" is the Mesh's active scalars: ParaView colours a new representation by the active
 * scalars, so Apply shows the body coloured by speed rather than in a solid colour.
 *
 * The physics lives in core (softbody::MassSpringSimulation, softbody::PbdSimulation; no VTK). This class only
 * translates: properties to core settings, the input to a core body, time requests to
 * `advance` calls, and core's arrays back to VTK arrays.
 *
 * Frames on the time grid are cached (see CacheMemoryLimit), so scrubbing back and replaying
 * cost no simulation; the cache and the simulation are dropped when the input or any property
 * that changes the motion changes (EndTime and CacheMemoryLimit do not).
 *
 * Units are SI throughout: lengths in the input's units are taken as meters.
 */
#ifndef vtkSoftBodyFilter_h
#define vtkSoftBodyFilter_h

#include "SoftBodyFiltersModule.h" // for export macro
#include "vtkSoftBodyParameterMacros.h" // for vtkSoftBodyParameterMacro
#include "vtkSoftBodyParameters.h"      // for vtkSoftBodyParameters
#include "vtkUnstructuredGridAlgorithm.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string
#include <vector> // for std::vector

class vtkPolyData;
struct vtkSoftBodyCoreSettings;
struct vtkSoftBodyObstacleConnection;
enum class vtkSoftBodyRunResult : int;
class vtkUnstructuredGrid;
namespace softbody
{
struct ObstacleSurface;
}
namespace vtkSoftBodyOutputAssembly
{
struct Outputs;
}

class SOFTBODYFILTERS_EXPORT vtkSoftBodyFilter : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkSoftBodyFilter* New();
  vtkTypeMacro(vtkSoftBodyFilter, vtkUnstructuredGridAlgorithm)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Every property as the user set it, with its default (vtkSoftBodyParameters.h).
  using Parameters = vtkSoftBodyParameters;
#ifndef __VTK_WRAP__
  // The property enumerations, as vtkSoftBodyFilter::MASS_SPRING, vtkSoftBodyFilter::XPBD, ...
  using enum vtkSoftBodyParameters::MethodType;
  using enum vtkSoftBodyParameters::XPBDMaterialType;
  using enum vtkSoftBodyParameters::SolverType;
  using enum vtkSoftBodyParameters::TimeStepModeType;
  using enum vtkSoftBodyParameters::IntegratorType;
  using enum vtkSoftBodyParameters::MaterialModeType;
  using enum vtkSoftBodyParameters::MaterialModelType;
  using enum vtkSoftBodyParameters::VolumetricFormulationType;
  using enum vtkSoftBodyParameters::FloorPlacementType;
  using enum vtkSoftBodyParameters::MassDistributionType;
  using enum vtkSoftBodyParameters::InvertedTetsType;
  using enum vtkSoftBodyParameters::DeviceType;
  using enum vtkSoftBodyParameters::CollisionsType;
  using enum vtkSoftBodyParameters::BroadPhaseType;
#endif
#ifndef __VTK_WRAP__
  const Parameters& GetParameters() const { return this->P; }
#endif

  /**
   * The optional render surface (input port 1) skinned onto the body (output port 3).
   */
  void SetSurfaceConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }

  /**
   * Obstacles (input port 2, optional and repeatable): any dataset, whose triangulated outer
   * surface the bodies collide with, one-sided (the free side is the one its triangles'
   * normals point to; see vtkSoftBodyObstacleInput). A time-dependent obstacle source is
   * requested at every frame time the simulation passes and moves with the velocity of its
   * vertices between frames.
   */
  void AddObstacleConnection(vtkAlgorithmOutput* output) { this->AddInputConnection(2, output); }
  void RemoveAllObstacles() { this->SetInputConnection(2, nullptr); }

  /**
   * Conditions (input port 3, optional and repeatable): outputs of Soft Body Condition, each a
   * load or boundary condition on a set of the body's points (found by position; see
   * vtkSoftBodyConditionInput), honoured by every method; reactions are reported by
   * Mass-Spring (vtkSoftBodyConditionOutput).
   */
  void AddConditionConnection(vtkAlgorithmOutput* output) { this->AddInputConnection(3, output); }
  void RemoveAllConditions() { this->SetInputConnection(3, nullptr); }

  ///@{
  /**
   * Method: MASS_SPRING (0, tetrahedra only), PBD (1) or XPBD (2) (tetrahedra, and line cells
   * as distance links; other cells move with their points).
   */
  vtkSoftBodyParameterMacro(Method, int);
  ///@}

  ///@{
  /**
   * PBD/XPBD solver: GAUSS_SEIDEL (SOR when Relaxation != 1), JACOBI (averaged, relaxed) or
   * PARALLEL_GAUSS_SEIDEL (graph-colored; same result at any thread count).
   */
  vtkSoftBodyParameterMacro(Solver, int);
  /// Iterations per (sub)step; the cap when ResidualTolerance > 0.
  vtkSoftBodyParameterMacro(Iterations, int);
  /// Stop iterating below this residual (constraint units); 0 = always run Iterations.
  vtkSoftBodyParameterMacro(ResidualTolerance, double);
  /// SOR factor (Gauss-Seidel) or Jacobi's relaxation, in (0, 2).
  vtkSoftBodyParameterMacro(Relaxation, double);
  /// Substeps per time step (each runs Iterations iterations).
  vtkSoftBodyParameterMacro(Substeps, int);
  ///@}

  ///@{
  /**
   * PBD stiffnesses in [0, 1] of links (distance), tet volumes and soft pins; applied per
   * iteration as 1 - (1 - k)^(1/Iterations). A pin stiffness of 1 fixes pinned points.
   */
  vtkSoftBodyParameterMacro(PBDLinkStiffness, double);
  vtkSoftBodyParameterMacro(PBDVolumeStiffness, double);
  vtkSoftBodyParameterMacro(PBDPinStiffness, double);
  ///@}

  ///@{
  /**
   * XPBD compliances (inverse stiffness): links [m/N], tet volumes [m^3/Pa] (the constraint is
   * V - V0), pins [m/N]; 0 is rigid (a pin compliance of 0 fixes pinned points).
   */
  vtkSoftBodyParameterMacro(XPBDLinkCompliance, double);
  vtkSoftBodyParameterMacro(XPBDVolumeCompliance, double);
  vtkSoftBodyParameterMacro(XPBDPinCompliance, double);
  /**
   * XPBD_COMPLIANCES (default) uses the compliances above; XPBD_YOUNGS_MODULUS derives each tet
   * edge's and tet's compliance from YoungsModulus and PoissonRatio exactly as Mass-Spring
   * derives its stiffnesses, so both methods rest where the same elastic energy is minimal.
   */
  vtkSoftBodyParameterMacro(XPBDMaterial, int);
  ///@}

  ///@{
  /**
   * PBD/XPBD materials: links break past BreakingStrain (relative to their original length;
   * 0 = never); past PlasticYield their rest length creeps toward the current length at
   * PlasticCreep [1/s] (0 = elastic); VelocityDamping [1/s] damps all motion.
   */
  vtkSoftBodyParameterMacro(BreakingStrain, double);
  vtkSoftBodyParameterMacro(PlasticYield, double);
  vtkSoftBodyParameterMacro(PlasticCreep, double);
  vtkSoftBodyParameterMacro(VelocityDamping, double);
  ///@}

  ///@{
  /**
   * Contacts (every method). Collisions: COLLISIONS_OFF (nothing, not even the floor),
   * COLLISIONS_OBSTACLES (default: the floor and the Obstacles input), COLLISIONS_BODIES (+ the
   * input's connected bodies against each other), COLLISIONS_BODIES_AND_SELF (+ each body
   * against itself). BroadPhase: BROAD_PHASE_AUTOMATIC (default), _BRUTE_FORCE, _UNIFORM_GRID,
   * _OCTREE (same contacts, different cost). CollisionMargin [m]: the thickness kept between a
   * point and what it touches, 0 (default) = automatic. StaticFriction and DynamicFriction
   * (Coulomb, >= 0; default 0.3 both): a contact sticks while the tangential push is below
   * StaticFriction times the normal one and slides with DynamicFriction otherwise.
   * Restitution in [0, 1]: the fraction of the normal approach speed kept after an impact.
   * The two frictions are separate properties, with no alias setting both, so that the panel
   * and a saved state always show which value is in force.
   */
  vtkSoftBodyParameterMacro(Collisions, int);
  vtkSoftBodyParameterMacro(BroadPhase, int);
  vtkSoftBodyParameterMacro(CollisionMargin, double);
  vtkSoftBodyParameterMacro(StaticFriction, double);
  vtkSoftBodyParameterMacro(DynamicFriction, double);
  vtkSoftBodyParameterMacro(Restitution, double);
  ///@}

  ///@{
  /**
   * Device: DEVICE_CPU (default) or DEVICE_GPU_EGL (OpenGL 4.3 compute shaders on a headless
   * EGL context; Mass-Spring only). When the GPU cannot start, the filter warns why and
   * simulates on the CPU; field data "Device" says which one ran.
   */
  vtkSoftBodyParameterMacro(Device, int);
  ///@}

  ///@{
  /**
   * Integrator: EULER, MIDPOINT, VERLET or EULER_CROMER (default, symplectic and cheap), or
   * the implicit IMPLICIT_EULER (Newton + PCG) and PROJECTIVE_DYNAMICS (prefactored
   * local/global iterations), stable at any step, or STATIC: the static equilibrium at each
   * frame (Newton on the elastic energy and gravity; the body must be held by pinned points)
   * (Mass-Spring on the CPU only).
   */
  vtkSoftBodyParameterMacro(Integrator, int);
  ///@}

  ///@{
  /**
   * Implicit integrators: the step's equations count as solved when the residual acceleration
   * is below ImplicitTolerance times the reference (gravity, or the speed over the step) (> 0;
   * 0 allowed for Projective Dynamics: always ImplicitMaxIterations iterations).
   * ImplicitMaxIterations: Newton or local/global iterations per step (>= 1).
   */
  vtkSoftBodyParameterMacro(ImplicitTolerance, double);
  vtkSoftBodyParameterMacro(ImplicitMaxIterations, int);
  ///@}

  ///@{
  /**
   * Time step [s]; 0 (default) picks 0.9 times the estimated stable step.
   */
  vtkSoftBodyParameterMacro(TimeStep, double);
  ///@}

  ///@{
  /**
   * Mass-Spring and XPBD: FIXED_STEP (TimeStep, or the automatic step) or ERROR_CONTROLLED:
   * each step chosen from a local error estimate so that the positions stay within
   * ErrorTolerance [m] of the exact motion over each simulated second (> 0); TimeStep > 0
   * then bounds the step. PBD refuses it (its stiffness changes with the step).
   */
  vtkSoftBodyParameterMacro(TimeStepMode, int);
  vtkSoftBodyParameterMacro(ErrorTolerance, double);
  ///@}

  ///@{
  /**
   * End of the simulated interval [s] (default 3). Must be > 0.
   */
  vtkSoftBodyParameterMacro(EndTime, double);
  ///@}

  ///@{
  /**
   * Interval between output frames [s] (default 0.04, i.e. 25 frames per second). Must be > 0.
   */
  vtkSoftBodyParameterMacro(FrameInterval, double);
  ///@}

  ///@{
  /**
   * Gravitational acceleration [m/s^2] (default 0 0 -9.81).
   */
  vtkSoftBodyVector3ParameterMacro(Gravity);
  ///@}

  ///@{
  /**
   * Floor: a plane with normal FloorNormal (pointing into free space) that points cannot cross.
   * On by default. A zero FloorNormal is an error. FloorPlacement says where it goes:
   * FLOOR_AUTOMATIC (default) through FloorOrigin [m], unless the body starts below that plane
   * (a mesh in scanner coordinates): then under the body, with a warning;
   * FLOOR_UNDER_THE_BODY through the body's lowest point along FloorNormal;
   * FLOOR_THROUGH_FLOOR_ORIGIN through FloorOrigin, a body below it lifted onto it at t = 0.
   * Field data FloorOrigin holds where it went.
   */
  vtkSoftBodyBooleanParameterMacro(Floor);
  vtkSoftBodyParameterMacro(FloorPlacement, int);
  vtkSoftBodyVector3ParameterMacro(FloorOrigin);
  vtkSoftBodyVector3ParameterMacro(FloorNormal);
  ///@}

  ///@{
  /**
   * Name of a point-data array marking pinned points (nonzero in any component = pinned; pinned
   * points never move). Empty or "None" (default) pins nothing.
   */
  vtkSoftBodyStringParameterMacro(PinnedPointsArray);
  ///@}

  ///@{
  /**
   * The initial state (every method): a uniform InitialVelocity [m/s] plus a spin
   * InitialAngularVelocity [rad/s] about the body's centre of mass, plus a point array
   * InitialVelocityArray [m/s]; and a start from a deformed state, rest + the point array
   * InitialDisplacementArray [m] (a saved frame's Displacement restarts a run where it stopped).
   * Held and pinned points keep their condition's state. "None" (default): none.
   */
  vtkSoftBodyVector3ParameterMacro(InitialVelocity);
  vtkSoftBodyVector3ParameterMacro(InitialAngularVelocity);
  vtkSoftBodyStringParameterMacro(InitialVelocityArray);
  vtkSoftBodyStringParameterMacro(InitialDisplacementArray);
  ///@}

  ///@{
  /**
   * MaterialModel (Mass-Spring): SPRING_NETWORK (default, the thesis's springs and volumes),
   * or the finite-element tets COROTATED and STABLE_NEO_HOOKEAN, whose YoungsModulus and
   * PoissonRatio (-1 < nu < 0.5) mean what they mean in a paper. The Mesh output then carries
   * GreenStrain, CauchyStress, VonMisesStress and StrainEnergyDensity per cell.
   */
  vtkSoftBodyParameterMacro(MaterialModel, int);
  ///@}

  ///@{
  /**
   * VolumetricFormulation (COROTATED and STABLE_NEO_HOOKEAN under Mass-Spring): PER_TET
   * (default; each linear tet keeps its own volume, which locks - responds too stiff - as nu
   * nears 0.5) or NODAL_AVERAGE (the volume term averaged at the points, Bonet and Burton 1998:
   * no locking, for nearly incompressible materials; Implicit Euler, BDF2, Static and the
   * explicit integrators, on the CPU).
   */
  vtkSoftBodyParameterMacro(VolumetricFormulation, int);
  ///@}

  ///@{
  /**
   * MaterialMode: PHYSICAL (default) derives the spring constants from YoungsModulus [Pa],
   * PoissonRatio [-] in [0, 0.5), Density [kg/m^3] and DampingTime [s]; RAW_CONSTANTS uses
   * DistanceStiffness [J], DistanceDamping [J s], VolumeStiffness [J], VolumeDamping [J s] and
   * TotalMass [kg] as they are.
   */
  vtkSoftBodyParameterMacro(MaterialMode, int);
  vtkSoftBodyParameterMacro(YoungsModulus, double);
  vtkSoftBodyParameterMacro(PoissonRatio, double);
  vtkSoftBodyParameterMacro(Density, double);
  vtkSoftBodyParameterMacro(DampingTime, double);
  ///@}

  ///@{
  /**
   * Per-cell materials (Mass-Spring, Physical mode): a numeric one-component cell array of the
   * input whose values replace YoungsModulus [Pa], PoissonRatio or Density [kg/m^3] cell by
   * cell (two tissues, one value per Gmsh physical group). Empty or "None" (default): uniform.
   */
  vtkSoftBodyStringParameterMacro(YoungsModulusArray);
  vtkSoftBodyStringParameterMacro(PoissonRatioArray);
  vtkSoftBodyStringParameterMacro(DensityArray);
  vtkSoftBodyParameterMacro(DistanceStiffness, double);
  vtkSoftBodyParameterMacro(DistanceDamping, double);
  vtkSoftBodyParameterMacro(VolumeStiffness, double);
  vtkSoftBodyParameterMacro(VolumeDamping, double);
  vtkSoftBodyParameterMacro(TotalMass, double);
  ///@}

  ///@{
  /**
   * MassDistribution: AVERAGE_INCIDENT_VOLUME (default) or LUMPED_VOLUME.
   * MaxInverseMass [1/kg]: lighter points are made heavier up to this bound; 0 (default) = off.
   */
  vtkSoftBodyParameterMacro(MassDistribution, int);
  vtkSoftBodyParameterMacro(MaxInverseMass, double);
  ///@}

  ///@{
  /**
   * StrainLimit [-]: largest allowed length / rest length of a spring, > 1; 0 (default) = off.
   * StrainLimitIterations: projection passes per step (default 4, >= 1).
   */
  vtkSoftBodyParameterMacro(StrainLimit, double);
  vtkSoftBodyParameterMacro(StrainLimitIterations, int);
  ///@}

  ///@{
  /**
   * InvertedTets: REORIENT (default; the simulation's copy is fixed and a warning is reported)
   * or REFUSE (an error).
   */
  vtkSoftBodyParameterMacro(InvertedTets, int);
  ///@}

  ///@{
  /**
   * Memory budget of the frame cache [MiB] (default 512). Frame 0 is kept even over budget.
   */
  vtkSoftBodyParameterMacro(CacheMemoryLimit, int);
  ///@}

  /**
   * Simulation steps actually run by this filter since it was created. Requests served from the
   * frame cache do not add to it (tests use it to prove cache hits).
   */
  unsigned long long GetSimulatedStepsTotal() const { return this->SimulatedStepsTotal; }

  /**
   * Number of frames currently held by the frame cache.
   */
  int GetNumberOfCachedFrames() const;

protected:
  vtkSoftBodyFilter();
  ~vtkSoftBodyFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  Parameters P;

private:
  vtkSoftBodyFilter(const vtkSoftBodyFilter&) = delete;
  void operator=(const vtkSoftBodyFilter&) = delete;

  class vtkInternals;

  /// The requested time, clamped to [0, EndTime] (0 when none or NaN).
  double RequestedTime(vtkInformation* requestInfo) const;
  /// The bodies this process simulates: under MPI this rank's whole bodies, gathered from the
  /// ranks' pieces (`surfaceConnected` or body collisions keep them all on rank 0); else the
  /// input. Null when there is nothing to simulate here (a rank without a body, an empty
  /// streamed piece).
  vtkUnstructuredGrid* LocalInput(vtkUnstructuredGrid* input,
    const vtkSoftBodyCoreSettings& settings, bool surfaceConnected, vtkInformation* requestInfo);
  /// Brings the simulation to time `t` (vtkSoftBodyFrameRunner::Simulate, with this filter's
  /// warnings, errors, progress and abort).
  vtkSoftBodyRunResult Simulate(vtkUnstructuredGrid* input, const vtkSoftBodyCoreSettings& settings,
    const std::vector<vtkSoftBodyObstacleConnection>& obstacles,
    std::vector<softbody::ObstacleSurface> deliveredNow, double t);
  /// Fills every output port from the simulation at its current time; false (reported) when
  /// the Surface input cannot be bound to the body.
  bool AssembleOutputs(vtkUnstructuredGrid* input, vtkPolyData* surface,
    const vtkSoftBodyOutputAssembly::Outputs& outputs);
  std::unique_ptr<vtkInternals> Internals;
  unsigned long long SimulatedStepsTotal = 0;
};

#endif
