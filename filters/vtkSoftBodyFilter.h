/**
 * @class   vtkSoftBodyFilter
 * @brief   Simulates a tetrahedral mesh as a mass-spring soft body and outputs it over time.
 *
 * The input is a vtkUnstructuredGrid of tetrahedra at rest (apply Tetrahedralize first if it
 * holds other cells). The filter is a time source: it advertises the times
 * 0, FrameInterval, 2 FrameInterval, ..., EndTime, and for a requested time it outputs
 *
 * - port 0 ("Mesh"): the input grid with its points moved, the input point and cell arrays passed
 *   through, point arrays "Velocity" [m/s] and "Displacement" [m], cell array "VolumeRatio"
 *   (current / rest volume) and field data "SimulationTime", "StepCount", "TimeStep",
 *   "StableTimeStep", "Integrator", "Plan", "StageSeconds", "Warnings", "TotalMass", "Device"
 *   (the device that ran the steps) and "GLRenderer" (the GPU's renderer; empty on the CPU);
 * - port 1 ("Particles"): a vtkPolyData with one vertex per point and point arrays "Velocity" and
 *   "InverseMass".
 *
 * The physics lives in softbody::MassSpringSimulation (core library, no VTK). This class only
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
#include "vtkUnstructuredGridAlgorithm.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class vtkPolyData;
class vtkUnstructuredGrid;

class SOFTBODYFILTERS_EXPORT vtkSoftBodyFilter : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkSoftBodyFilter* New();
  vtkTypeMacro(vtkSoftBodyFilter, vtkUnstructuredGridAlgorithm)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum MethodType
  {
    MASS_SPRING = 0
  };
  enum IntegratorType
  {
    EULER = 0,
    MIDPOINT = 1,
    VERLET = 2,
    EULER_CROMER = 3
  };
  enum MaterialModeType
  {
    PHYSICAL = 0,
    RAW_CONSTANTS = 1
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

  ///@{
  /**
   * Method: the simulation model. Only MASS_SPRING (0) exists for now.
   */
  vtkSetClampMacro(Method, int, MASS_SPRING, MASS_SPRING);
  vtkGetMacro(Method, int);
  ///@}

  ///@{
  /**
   * Device: DEVICE_CPU (default) or DEVICE_GPU_EGL (OpenGL 4.3 compute shaders on a headless
   * EGL context; Mass-Spring only). When the GPU cannot start, the filter warns why and
   * simulates on the CPU; field data "Device" says which one ran.
   */
  vtkSetClampMacro(Device, int, DEVICE_CPU, DEVICE_GPU_EGL);
  vtkGetMacro(Device, int);
  ///@}

  ///@{
  /**
   * Integrator: EULER, MIDPOINT, VERLET or EULER_CROMER (default, symplectic and cheap).
   */
  vtkSetClampMacro(Integrator, int, EULER, EULER_CROMER);
  vtkGetMacro(Integrator, int);
  ///@}

  ///@{
  /**
   * Time step [s]; 0 (default) picks 0.9 times the estimated stable step.
   */
  vtkSetClampMacro(TimeStep, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(TimeStep, double);
  ///@}

  ///@{
  /**
   * End of the simulated interval [s] (default 3). Must be > 0.
   */
  vtkSetClampMacro(EndTime, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(EndTime, double);
  ///@}

  ///@{
  /**
   * Interval between output frames [s] (default 0.04, i.e. 25 frames per second). Must be > 0.
   */
  vtkSetClampMacro(FrameInterval, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(FrameInterval, double);
  ///@}

  ///@{
  /**
   * Gravitational acceleration [m/s^2] (default 0 0 -9.81).
   */
  vtkSetVector3Macro(Gravity, double);
  vtkGetVector3Macro(Gravity, double);
  ///@}

  ///@{
  /**
   * Floor: a plane through FloorOrigin [m] with normal FloorNormal (pointing into free space)
   * that points cannot cross. On by default. A zero FloorNormal is an error.
   */
  vtkSetMacro(Floor, vtkTypeBool);
  vtkGetMacro(Floor, vtkTypeBool);
  vtkBooleanMacro(Floor, vtkTypeBool);
  vtkSetVector3Macro(FloorOrigin, double);
  vtkGetVector3Macro(FloorOrigin, double);
  vtkSetVector3Macro(FloorNormal, double);
  vtkGetVector3Macro(FloorNormal, double);
  ///@}

  ///@{
  /**
   * Name of a point-data array marking pinned points (nonzero in any component = pinned; pinned
   * points never move). Empty or "None" (default) pins nothing.
   */
  vtkSetStdStringFromCharMacro(PinnedPointsArray);
  vtkGetCharFromStdStringMacro(PinnedPointsArray);
  ///@}

  ///@{
  /**
   * MaterialMode: PHYSICAL (default) derives the spring constants from YoungsModulus [Pa],
   * PoissonRatio [-] in [0, 0.5), Density [kg/m^3] and DampingTime [s]; RAW_CONSTANTS uses
   * DistanceStiffness [J], DistanceDamping [J s], VolumeStiffness [J], VolumeDamping [J s] and
   * TotalMass [kg] as they are.
   */
  vtkSetClampMacro(MaterialMode, int, PHYSICAL, RAW_CONSTANTS);
  vtkGetMacro(MaterialMode, int);
  vtkSetClampMacro(YoungsModulus, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(YoungsModulus, double);
  vtkSetClampMacro(PoissonRatio, double, 0.0, 0.5);
  vtkGetMacro(PoissonRatio, double);
  vtkSetClampMacro(Density, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Density, double);
  vtkSetClampMacro(DampingTime, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(DampingTime, double);
  vtkSetClampMacro(DistanceStiffness, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(DistanceStiffness, double);
  vtkSetClampMacro(DistanceDamping, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(DistanceDamping, double);
  vtkSetClampMacro(VolumeStiffness, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(VolumeStiffness, double);
  vtkSetClampMacro(VolumeDamping, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(VolumeDamping, double);
  vtkSetClampMacro(TotalMass, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(TotalMass, double);
  ///@}

  ///@{
  /**
   * MassDistribution: AVERAGE_INCIDENT_VOLUME (default) or LUMPED_VOLUME.
   * MaxInverseMass [1/kg]: lighter points are made heavier up to this bound; 0 (default) = off.
   */
  vtkSetClampMacro(MassDistribution, int, AVERAGE_INCIDENT_VOLUME, LUMPED_VOLUME);
  vtkGetMacro(MassDistribution, int);
  vtkSetClampMacro(MaxInverseMass, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaxInverseMass, double);
  ///@}

  ///@{
  /**
   * StrainLimit [-]: largest allowed length / rest length of a spring, > 1; 0 (default) = off.
   * StrainLimitIterations: projection passes per step (default 4, >= 1).
   */
  vtkSetClampMacro(StrainLimit, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(StrainLimit, double);
  vtkSetClampMacro(StrainLimitIterations, int, 1, VTK_INT_MAX);
  vtkGetMacro(StrainLimitIterations, int);
  ///@}

  ///@{
  /**
   * InvertedTets: REORIENT (default; the simulation's copy is fixed and a warning is reported)
   * or REFUSE (an error).
   */
  vtkSetClampMacro(InvertedTets, int, REORIENT, REFUSE);
  vtkGetMacro(InvertedTets, int);
  ///@}

  ///@{
  /**
   * Memory budget of the frame cache [MiB] (default 512). Frame 0 is kept even over budget.
   */
  vtkSetClampMacro(CacheMemoryLimit, int, 0, VTK_INT_MAX);
  vtkGetMacro(CacheMemoryLimit, int);
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

  int Method = MASS_SPRING;
  int Device = DEVICE_CPU;
  int Integrator = EULER_CROMER;
  double TimeStep = 0.0;
  double EndTime = 3.0;
  double FrameInterval = 0.04;
  double Gravity[3] = { 0.0, 0.0, -9.81 };
  vtkTypeBool Floor = 1;
  double FloorOrigin[3] = { 0.0, 0.0, 0.0 };
  double FloorNormal[3] = { 0.0, 0.0, 1.0 };
  std::string PinnedPointsArray;
  int MaterialMode = PHYSICAL;
  double YoungsModulus = 1.0e5;
  double PoissonRatio = 0.3;
  double Density = 1100.0;
  double DampingTime = 2.0e-3;
  // Raw-mode defaults; the constructor copies them from softbody::RawConstants.
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

private:
  vtkSoftBodyFilter(const vtkSoftBodyFilter&) = delete;
  void operator=(const vtkSoftBodyFilter&) = delete;

  /// Why the properties cannot be simulated, or an empty string.
  std::string ValidateParameters() const;
  /// Builds the simulation (and empties the cache) unless input and parameters are unchanged.
  bool PrepareSimulation(vtkUnstructuredGrid* input);
  /// Brings the simulation to time `t` through the cache; false when aborted.
  bool AdvanceTo(double t);
  void FillMesh(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output);
  void FillParticles(vtkUnstructuredGrid* mesh, vtkPolyData* output);

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
  unsigned long long SimulatedStepsTotal = 0;
};

#endif
