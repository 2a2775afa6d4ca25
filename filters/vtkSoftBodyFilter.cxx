#include "vtkSoftBodyFilter.h"

#include "vtkSoftBodyFrameCache.h"
#include "vtkSoftBodyInputConversion.h"
#include "vtkSoftBodyPbdAdapter.h"
#include "vtkSoftBodySkin.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#ifdef SOFTBODY_WITH_GPU
#include "softbody/gpu/mass_spring_gpu_simulation.h"
#endif

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkSoftBodyFilter);

namespace
{
// More frames than this is a typo (e.g. FrameInterval in ms), not a plan; the advertised list of
// times would also grow unreasonably.
constexpr double kMaxFrames = 1.0e6;

softbody::Integrator CoreIntegrator(int integrator)
{
  switch (integrator)
  {
    case vtkSoftBodyFilter::EULER:
      return softbody::Integrator::Euler;
    case vtkSoftBodyFilter::MIDPOINT:
      return softbody::Integrator::Midpoint;
    case vtkSoftBodyFilter::VERLET:
      return softbody::Integrator::Verlet;
    default:
      return softbody::Integrator::EulerCromer;
  }
}

bool IsFinite(const double v[3])
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

softbody::Vec3 ToVec3(const double v[3])
{
  return softbody::Vec3(v[0], v[1], v[2]);
}

// Copies core's vectors into a new 3-component VTK array. A copy, not zero-copy: the
// simulation overwrites its arrays on the next request while the output may still be in use.
vtkSmartPointer<vtkDoubleArray> MakeVectorArray(
  const char* name, const std::vector<softbody::Vec3>& values)
{
  static_assert(sizeof(softbody::Vec3) == 3 * sizeof(double), "Vec3 must be 3 packed doubles");
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  if (!values.empty())
  {
    const double* first = values.front().data();
    std::copy(first, first + 3 * values.size(), array->GetPointer(0));
  }
  return array;
}

vtkSmartPointer<vtkDoubleArray> MakeScalarArray(const char* name, const std::vector<double>& values)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  std::copy(values.begin(), values.end(), array->GetPointer(0));
  return array;
}

vtkSmartPointer<vtkStringArray> MakeStringArray(
  const char* name, const std::vector<std::string>& values)
{
  auto array = vtkSmartPointer<vtkStringArray>::New();
  array->SetName(name);
  array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    array->SetValue(static_cast<vtkIdType>(i), values[i]);
  }
  return array;
}

// Names of the devices in field data "Device" (the XML's enumeration texts).
constexpr const char* kDeviceNames[] = { "CPU", "GPU (EGL)" };

/// The GPU mass-spring stepper, or null with the reason why not (then the caller falls back
/// to the CPU). Invalid input throws InvalidInputError as the CPU stepper would.
std::unique_ptr<softbody::Simulation> MakeGpuSimulation(const softbody::BodyDescription& body,
  const softbody::SceneSettings& scene, std::string& renderer, std::string& whyNot)
{
#ifdef SOFTBODY_WITH_GPU
  std::unique_ptr<softbody::gpu::MassSpringGpuSimulation> simulation =
    softbody::gpu::tryCreateGpuMassSpring(body, scene, whyNot);
  if (simulation)
  {
    renderer = simulation->glRenderer();
  }
  return simulation;
#else
  (void)body;
  (void)scene;
  (void)renderer;
  whyNot = "this build of the plugin has no GPU backend (SOFTBODY_ENABLE_GPU was off).";
  return nullptr;
#endif
}

vtkSmartPointer<vtkPoints> MakePoints(const std::vector<softbody::Vec3>& positions)
{
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(MakeVectorArray("Points", positions));
  return points;
}
} // namespace

//------------------------------------------------------------------------------
// Run-time state kept between requests: the simulation, its frame cache and what they were
// built from.
class vtkSoftBodyFilter::vtkInternals
{
public:
  std::unique_ptr<softbody::Simulation> Simulation;
  /// Set when the simulation is PBD/XPBD (it is then also `Simulation`).
  softbody::PbdSimulation* Pbd = nullptr;
  vtkSoftBodyPbdAdapter PbdAdapter;
  /// The optional render surface's binding to the body (kept while both are unchanged).
  vtkSoftBodySkin Skin;
  vtkSoftBodyFrameCache Cache;
  /// Grid frame the simulation's state is exactly at; -1 when between frames or unknown.
  int SimulationFrame = -1;

  // The cache key: which input (object and modification time) and which parameters the
  // simulation was built from.
  const vtkDataObject* Input = nullptr; // identity only, never dereferenced
  vtkMTimeType InputMTime = 0;
  std::vector<double> Parameters;
  std::string PinnedPointsArray;

  // The device the simulation runs on (may differ from the Device property after a fallback).
  int DeviceUsed = vtkSoftBodyFilter::DEVICE_CPU;
  std::string GLRenderer;
  std::string DeviceWarning; ///< why the GPU was not used although asked for; empty otherwise

  void Discard()
  {
    this->Simulation.reset();
    this->Pbd = nullptr;
    this->Cache.Clear();
    this->SimulationFrame = -1;
    this->Input = nullptr;
    this->Parameters.clear();
    this->DeviceUsed = vtkSoftBodyFilter::DEVICE_CPU;
    this->GLRenderer.clear();
    this->DeviceWarning.clear();
  }
};

//------------------------------------------------------------------------------
vtkSoftBodyFilter::vtkSoftBodyFilter()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(4);
  // One source of truth for the raw-mode defaults: core's RawConstants.
  const softbody::RawConstants raw;
  this->DistanceStiffness = raw.distanceStiffness;
  this->DistanceDamping = raw.distanceDamping;
  this->VolumeStiffness = raw.volumeStiffness;
  this->VolumeDamping = raw.volumeDamping;
  this->TotalMass = raw.totalMass;
}

//------------------------------------------------------------------------------
vtkSoftBodyFilter::~vtkSoftBodyFilter() = default;

//------------------------------------------------------------------------------
int vtkSoftBodyFilter::GetNumberOfCachedFrames() const
{
  return static_cast<int>(this->Internals->Cache.GetNumberOfFrames());
}

//------------------------------------------------------------------------------
int vtkSoftBodyFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    // The render surface to skin onto the body: optional.
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
}

//------------------------------------------------------------------------------
int vtkSoftBodyFilter::FillOutputPortInformation(int port, vtkInformation* info)
{
  const char* types[] = { "vtkUnstructuredGrid", "vtkPolyData", "vtkTable", "vtkPolyData" };
  info->Set(vtkDataObject::DATA_TYPE_NAME(), types[std::min(port, 3)]);
  return 1;
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyFilter::ValidateParameters() const
{
  // Written as !(x > 0) so that NaN (which the clamp setters let through) is rejected too.
  std::ostringstream msg;
  if (!(this->EndTime > 0.0) || !std::isfinite(this->EndTime))
  {
    msg << "EndTime must be > 0 s (got " << this->EndTime << ").";
  }
  else if (!(this->FrameInterval > 0.0) || !std::isfinite(this->FrameInterval))
  {
    msg << "FrameInterval must be > 0 s (got " << this->FrameInterval << ").";
  }
  else if (this->EndTime / this->FrameInterval > kMaxFrames)
  {
    msg << "EndTime / FrameInterval gives more than " << kMaxFrames
        << " frames; increase FrameInterval.";
  }
  else if (!(this->TimeStep >= 0.0) || !std::isfinite(this->TimeStep))
  {
    msg << "TimeStep must be >= 0 s (0 = automatic; got " << this->TimeStep << ").";
  }
  else if (!IsFinite(this->Gravity) || !IsFinite(this->FloorOrigin) || !IsFinite(this->FloorNormal))
  {
    msg << "Gravity, FloorOrigin and FloorNormal must be finite.";
  }
  else if (this->Floor && vtkMath::Norm(this->FloorNormal) == 0.0)
  {
    msg << "FloorNormal must not be the zero vector.";
  }
  else if (!(this->DampingTime >= 0.0) || !(this->MaxInverseMass >= 0.0))
  {
    msg << "DampingTime and MaxInverseMass must be >= 0.";
  }
  else if (this->Method != MASS_SPRING)
  {
    // PBD/XPBD settings are checked by core, which names the property.
  }
  else if (this->MaterialMode == PHYSICAL && !(this->YoungsModulus > 0.0))
  {
    msg << "YoungsModulus must be > 0 Pa (got " << this->YoungsModulus << ").";
  }
  else if (this->MaterialMode == PHYSICAL &&
    !(this->PoissonRatio >= 0.0 && this->PoissonRatio < 0.5))
  {
    msg << "PoissonRatio must be in [0, 0.5) (got " << this->PoissonRatio << ").";
  }
  else if (this->MaterialMode == PHYSICAL && !(this->Density > 0.0))
  {
    msg << "Density must be > 0 kg/m^3 (got " << this->Density << ").";
  }
  else if (this->MaterialMode == RAW_CONSTANTS && !(this->TotalMass > 0.0))
  {
    msg << "TotalMass must be > 0 kg (got " << this->TotalMass << ").";
  }
  else if (this->StrainLimit != 0.0 && !(this->StrainLimit > 1.0))
  {
    msg << "StrainLimit must be 0 (off) or > 1 (got " << this->StrainLimit << ").";
  }
  return msg.str();
}

//------------------------------------------------------------------------------
int vtkSoftBodyFilter::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  // The filter makes its own time: whatever times the input advertised are replaced on both
  // ports, so a static input does not limit the animation and a temporal one does not confuse it.
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(port);
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  }
  if (!(this->EndTime > 0.0) || !(this->FrameInterval > 0.0) ||
    this->EndTime / this->FrameInterval > kMaxFrames)
  {
    // RequestData reports it; advertising no times keeps the pipeline sane meanwhile.
    return 1;
  }
  const std::vector<double> times = vtkSoftBodyFrameGrid{ this->FrameInterval, this->EndTime }.Times();
  const double range[2] = { 0.0, this->EndTime };
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(port);
    outInfo->Set(
      vtkStreamingDemandDrivenPipeline::TIME_STEPS(), times.data(), static_cast<int>(times.size()));
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkSoftBodyFilter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // The requested time is ours, not the input's: the input is the body at rest. Forwarding the
  // time would make a temporal input re-execute on every frame and so invalidate the cache.
  for (int port = 0; port < 2; ++port)
  {
    vtkInformation* inInfo = inputVector[port]->GetInformationObject(0);
    if (inInfo)
    {
      inInfo->Remove(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkSoftBodyFilter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Fetch info and downcast.
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* mesh = vtkUnstructuredGrid::GetData(outputVector, 0);
  vtkPolyData* particles = vtkPolyData::GetData(outputVector, 1);
  vtkTable* convergence = vtkTable::GetData(outputVector, 2);
  vtkPolyData* skinned = vtkPolyData::GetData(outputVector, 3);
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[1], 0); // optional
  if (!input || !mesh || !particles || !convergence || !skinned)
  {
    vtkErrorMacro("Missing input or output data object.");
    return 0;
  }

  // The requested time comes on the port the request came from (the other port may hold a
  // stale request); both outputs are produced for it.
  int fromPort = 0;
  if (request->Has(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()))
  {
    fromPort = std::max(0, request->Get(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()));
  }
  vtkInformation* requestInfo = outputVector->GetInformationObject(fromPort);
  double t = 0.0;
  if (requestInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    t = requestInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  }

  // Validate.
  const std::string parameterError = this->ValidateParameters();
  if (!parameterError.empty())
  {
    // The cache stays: correcting the value back finds it still valid.
    vtkErrorMacro(<< parameterError);
    return 0;
  }
  t = std::isnan(t) ? 0.0 : std::min(std::max(t, 0.0), this->EndTime);

  auto stampTime = [&]() {
    for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
    {
      vtkDataObject::GetData(outputVector, port)
        ->GetInformation()
        ->Set(vtkDataObject::DATA_TIME_STEP(), t);
    }
  };

  // In a parallel run a rank may hold no piece of the body: it outputs nothing, quietly, and
  // takes part in nothing, so no rank waits on it.
  if ((input->GetNumberOfPoints() == 0 || input->GetNumberOfCells() == 0) &&
    requestInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) > 1)
  {
    stampTime();
    return 1;
  }

  // Compute. Core reports unusable input and divergence by exceptions; they must not cross
  // into the pipeline, and a simulation that threw is not trusted again.
  try
  {
    if (!this->PrepareSimulation(input))
    {
      return 0;
    }
    if (!this->AdvanceTo(t))
    {
      // Aborted: CheckAbort has flagged the outputs; the executive empties them.
      return 1;
    }
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    this->Internals->Discard();
    return 0;
  }
  catch (const softbody::SimulationDivergedError& e)
  {
    // Core's message already names the time and what to change.
    vtkErrorMacro(<< e.what());
    this->Internals->Discard();
    return 0;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "The simulation failed: " << e.what());
    this->Internals->Discard();
    return 0;
  }

  // Assemble the outputs.
  this->FillMesh(input, mesh);
  this->FillParticles(mesh, particles);
  this->FillConvergence(convergence);
  if (surface)
  {
    const std::string skinError = this->Internals->Skin.Bind(input, surface);
    if (!skinError.empty())
    {
      vtkErrorMacro(<< "Cannot skin the Surface input onto the body: " << skinError);
      return 0;
    }
    this->Internals->Skin.Fill(surface, this->Internals->Simulation->positions(), skinned);
  }
  stampTime();
  return 1;
}

//------------------------------------------------------------------------------
bool vtkSoftBodyFilter::PrepareSimulation(vtkUnstructuredGrid* input)
{
  vtkInternals& internals = *this->Internals;
  internals.Cache.SetMemoryLimit(static_cast<std::size_t>(this->CacheMemoryLimit) << 20);

  // Everything that changes the motion. EndTime and CacheMemoryLimit do not, so changing them
  // keeps the cache.
  const std::vector<double> parameters = { double(this->Method), double(this->Integrator),
    this->TimeStep, this->FrameInterval, this->Gravity[0], this->Gravity[1], this->Gravity[2],
    double(this->Floor), this->FloorOrigin[0], this->FloorOrigin[1], this->FloorOrigin[2],
    this->FloorNormal[0], this->FloorNormal[1], this->FloorNormal[2], double(this->MaterialMode),
    this->YoungsModulus, this->PoissonRatio, this->Density, this->DampingTime,
    this->DistanceStiffness, this->DistanceDamping, this->VolumeStiffness, this->VolumeDamping,
    this->TotalMass, double(this->MassDistribution), this->MaxInverseMass, this->StrainLimit,
    double(this->StrainLimitIterations), double(this->InvertedTets), double(this->Solver),
    double(this->Iterations), this->ResidualTolerance, this->Relaxation, double(this->Substeps),
    this->PBDLinkStiffness, this->PBDVolumeStiffness, this->PBDPinStiffness,
    this->XPBDLinkCompliance, this->XPBDVolumeCompliance, this->XPBDPinCompliance,
    this->BreakingStrain, this->PlasticYield, this->PlasticCreep, this->Friction,
    this->Restitution, this->VelocityDamping, double(this->Device), double(this->XPBDMaterial) };
  const std::string pinned =
    vtkSoftBodyInputConversion::IsNoArray(this->PinnedPointsArray) ? "" : this->PinnedPointsArray;
  if (internals.Simulation && internals.Input == input &&
    internals.InputMTime == input->GetMTime() && internals.Parameters == parameters &&
    internals.PinnedPointsArray == pinned)
  {
    return true;
  }
  internals.Discard();

  if (this->Method == PBD || this->Method == XPBD)
  {
    std::string error;
    std::unique_ptr<softbody::PbdSimulation> pbd = internals.PbdAdapter.Create(*this, input, pinned, error);
    if (!pbd)
    {
      vtkErrorMacro(<< error);
      return false;
    }
    internals.Pbd = pbd.get();
    internals.Simulation = std::move(pbd);
    if (this->Device == DEVICE_GPU_EGL)
    {
      internals.DeviceWarning = "Device GPU (EGL) runs Mass-Spring only; PBD and XPBD run on the CPU.";
      vtkWarningMacro(<< internals.DeviceWarning);
    }
  }
  else if (!this->CreateMassSpring(input, pinned))
  {
    return false;
  }
  internals.Cache.Insert(0, internals.Simulation->state());
  internals.SimulationFrame = 0;
  internals.Input = input;
  internals.InputMTime = input->GetMTime();
  internals.Parameters = parameters;
  internals.PinnedPointsArray = pinned;

  // Said once per simulation, not on every frame; the Warnings field data repeats them.
  const std::vector<std::string>& warnings = internals.Simulation->warnings();
  if (!warnings.empty())
  {
    std::ostringstream msg;
    for (const std::string& warning : warnings)
    {
      msg << "\n  " << warning;
    }
    vtkWarningMacro(<< "Soft body set up with warnings:" << msg.str());
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkSoftBodyFilter::CreateMassSpring(vtkUnstructuredGrid* input, const std::string& pinned)
{
  vtkInternals& internals = *this->Internals;
  softbody::BodyDescription body;
  const std::string inputError = vtkSoftBodyInputConversion::Convert(input, pinned, body);
  if (!inputError.empty())
  {
    vtkErrorMacro(<< inputError);
    return false;
  }

  softbody::MaterialSettings& material = body.material;
  material.mode = this->MaterialMode == RAW_CONSTANTS ? softbody::MaterialMode::Raw
                                                      : softbody::MaterialMode::Physical;
  material.physical.youngsModulus = this->YoungsModulus;
  material.physical.poissonRatio = this->PoissonRatio;
  material.physical.density = this->Density;
  material.physical.dampingTime = this->DampingTime;
  material.raw.distanceStiffness = this->DistanceStiffness;
  material.raw.distanceDamping = this->DistanceDamping;
  material.raw.volumeStiffness = this->VolumeStiffness;
  material.raw.volumeDamping = this->VolumeDamping;
  material.raw.totalMass = this->TotalMass;
  material.massDistribution = this->MassDistribution == LUMPED_VOLUME
    ? softbody::MassDistribution::LumpedVolume
    : softbody::MassDistribution::AverageIncidentVolume;
  material.maxInverseMass = this->MaxInverseMass;

  softbody::SceneSettings scene;
  scene.integrator = CoreIntegrator(this->Integrator);
  scene.timeStep = this->TimeStep;
  scene.gravity = ToVec3(this->Gravity);
  scene.floorEnabled = this->Floor != 0;
  scene.floor.origin = ToVec3(this->FloorOrigin);
  scene.floor.normal = ToVec3(this->FloorNormal);
  scene.strainLimit = this->StrainLimit;
  scene.strainLimitIterations = this->StrainLimitIterations;
  scene.invertedTets = this->InvertedTets == REFUSE ? softbody::InvertedTetPolicy::Refuse
                                                    : softbody::InvertedTetPolicy::Reorient;

  // Throws InvalidInputError for bad geometry or material; the caller reports it.
  if (this->Device == DEVICE_GPU_EGL && this->Method == MASS_SPRING)
  {
    std::string whyNot;
    internals.Simulation = MakeGpuSimulation(body, scene, internals.GLRenderer, whyNot);
    if (internals.Simulation)
    {
      internals.DeviceUsed = DEVICE_GPU_EGL;
    }
    else
    {
      internals.DeviceWarning = "Device GPU (EGL) is unavailable, simulating on the CPU: " + whyNot;
      vtkWarningMacro(<< internals.DeviceWarning);
    }
  }
  if (!internals.Simulation)
  {
    internals.Simulation =
      std::make_unique<softbody::MassSpringSimulation>(std::move(body), scene);
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkSoftBodyFilter::AdvanceTo(double t)
{
  vtkInternals& internals = *this->Internals;
  softbody::Simulation& simulation = *internals.Simulation;
  const vtkSoftBodyFrameGrid grid{ this->FrameInterval, this->EndTime };
  bool onGrid = true;
  const int target = grid.FrameOf(t, onGrid);

  // Resume from the latest cached frame at or before the target, unless the simulation itself
  // is already at a frame that is at least as close (it may be one the cache evicted).
  int cached = -1;
  const softbody::DynamicState* snapshot = internals.Cache.FindLatestAtOrBefore(target, cached);
  const bool simulationIsCloser = internals.SimulationFrame >= 0 &&
    internals.SimulationFrame <= target && internals.SimulationFrame >= cached;
  if (!simulationIsCloser)
  {
    if (!snapshot)
    {
      // Frame 0 is never evicted, so this cannot happen; fail loudly rather than guess.
      throw std::logic_error("the frame cache lost frame 0");
    }
    simulation.restoreState(*snapshot);
    internals.SimulationFrame = cached;
  }

  // Progress runs over the frames still to simulate (plus the final partial interval).
  const int first = internals.SimulationFrame;
  const int framesToRun = target - first + (onGrid ? 0 : 1);
  if (framesToRun <= 0)
  {
    return true;
  }
  double lastReported = -1.0;
  int framesDone = 0;
  bool aborted = false;
  // Called by core during advance(); reports at most every 0.5% and checks abort there, since
  // CheckAbort walks the pipeline and core may call this every step.
  const softbody::ProgressCallback progress = [&](double fraction) {
    const double total = (framesDone + fraction) / framesToRun;
    if (total - lastReported < 0.005)
    {
      return true;
    }
    lastReported = total;
    this->UpdateProgress(total);
    aborted = this->CheckAbort();
    return !aborted;
  };

  auto runTo = [&](double endTime) {
    const unsigned long long before = simulation.stepCount();
    const softbody::AdvanceStatus status = simulation.advance(endTime, progress);
    this->SimulatedStepsTotal += simulation.stepCount() - before;
    return status == softbody::AdvanceStatus::Completed && !aborted;
  };

  for (int k = first + 1; k <= target; ++k)
  {
    if (this->CheckAbort() || !runTo(k * this->FrameInterval))
    {
      internals.SimulationFrame = -1; // stopped somewhere inside frame k
      return false;
    }
    internals.SimulationFrame = k;
    internals.Cache.Insert(k, simulation.state());
    ++framesDone;
  }
  if (!onGrid)
  {
    // Off-grid times (only EndTime, or a time a script asks for) are not cached: the next
    // request resumes from the grid frame before them.
    internals.SimulationFrame = -1;
    if (this->CheckAbort() || !runTo(t))
    {
      return false;
    }
  }
  this->UpdateProgress(1.0);
  return true;
}

//------------------------------------------------------------------------------
void vtkSoftBodyFilter::FillMesh(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output)
{
  const softbody::Simulation& simulation = *this->Internals->Simulation;

  // Same cells (shared, not copied), new points; the input's arrays pass through.
  output->CopyStructure(input);
  output->SetPoints(MakePoints(simulation.positions()));
  output->GetPointData()->PassData(input->GetPointData());
  output->GetCellData()->PassData(input->GetCellData());
  output->GetFieldData()->PassData(input->GetFieldData());

  const std::vector<softbody::Vec3>& positions = simulation.positions();
  const std::vector<softbody::Vec3>& rest = simulation.restPositions();
  std::vector<softbody::Vec3> displacement(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    displacement[i] = positions[i] - rest[i];
  }
  output->GetPointData()->AddArray(MakeVectorArray("Velocity", simulation.velocities()));
  output->GetPointData()->AddArray(MakeVectorArray("Displacement", displacement));

  // Core keeps the tets in input cell order, so the ratios map onto the input cells; a PBD
  // input that mixes tets with other cells maps them through the adapter (NaN for non-tets).
  std::vector<double> ratios = simulation.tetVolumeRatios();
  if (this->Internals->Pbd && !ratios.empty())
  {
    ratios = this->Internals->PbdAdapter.PerInputCell(ratios, input->GetNumberOfCells());
  }
  if (static_cast<vtkIdType>(ratios.size()) == input->GetNumberOfCells())
  {
    output->GetCellData()->AddArray(MakeScalarArray("VolumeRatio", ratios));
  }

  vtkFieldData* field = output->GetFieldData();
  field->AddArray(MakeScalarArray("SimulationTime", { simulation.time() }));
  auto steps = vtkSmartPointer<vtkIdTypeArray>::New();
  steps->SetName("StepCount");
  steps->InsertNextValue(static_cast<vtkIdType>(simulation.stepCount()));
  field->AddArray(steps);
  field->AddArray(MakeScalarArray("TimeStep", { simulation.stepSize() }));
  field->AddArray(MakeScalarArray("StableTimeStep", { simulation.estimatedStableStep() }));
  field->AddArray(MakeScalarArray("TotalMass", { simulation.totalMass() }));

  field->AddArray(MakeStringArray(
    "Integrator", { softbody::integratorName(CoreIntegrator(this->Integrator)) }));
  if (const softbody::PbdSimulation* pbd = this->Internals->Pbd)
  {
    this->Internals->PbdAdapter.AddBrokenCells(*pbd, output);
    vtkSoftBodyPbdAdapter::AddConvergenceFields(*pbd, output);
  }

  // StageSeconds is parallel to Plan: each planned stage's accumulated wall time.
  std::vector<std::string> plan;
  std::vector<double> seconds;
  for (const softbody::StageTiming& timing : simulation.stageTimings())
  {
    plan.push_back(timing.label);
    seconds.push_back(timing.seconds);
  }
  field->AddArray(MakeStringArray("Plan", plan));
  field->AddArray(MakeScalarArray("StageSeconds", seconds));
  std::vector<std::string> warnings = simulation.warnings();
  if (!this->Internals->DeviceWarning.empty())
  {
    warnings.push_back(this->Internals->DeviceWarning);
  }
  field->AddArray(MakeStringArray("Warnings", warnings));
  field->AddArray(MakeStringArray("Device", { kDeviceNames[this->Internals->DeviceUsed] }));
  field->AddArray(MakeStringArray("GLRenderer", { this->Internals->GLRenderer }));
}

//------------------------------------------------------------------------------
void vtkSoftBodyFilter::FillParticles(vtkUnstructuredGrid* mesh, vtkPolyData* output)
{
  const softbody::Simulation& simulation = *this->Internals->Simulation;
  const vtkIdType numPoints = mesh->GetNumberOfPoints();

  // One vertex cell per point: offsets 0..n, connectivity 0..n-1.
  auto offsets = vtkSmartPointer<vtkIdTypeArray>::New();
  offsets->SetNumberOfValues(numPoints + 1);
  std::iota(offsets->GetPointer(0), offsets->GetPointer(0) + numPoints + 1, vtkIdType(0));
  auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
  connectivity->SetNumberOfValues(numPoints);
  std::iota(connectivity->GetPointer(0), connectivity->GetPointer(0) + numPoints, vtkIdType(0));
  auto verts = vtkSmartPointer<vtkCellArray>::New();
  verts->SetData(offsets, connectivity);

  // The points and velocities are the mesh's own arrays, shared rather than copied again.
  output->SetPoints(mesh->GetPoints());
  output->SetVerts(verts);
  output->GetPointData()->AddArray(mesh->GetPointData()->GetArray("Velocity"));
  output->GetPointData()->AddArray(MakeScalarArray("InverseMass", simulation.inverseMasses()));
}

//------------------------------------------------------------------------------
void vtkSoftBodyFilter::FillConvergence(vtkTable* output)
{
  if (const softbody::PbdSimulation* pbd = this->Internals->Pbd)
  {
    vtkSoftBodyPbdAdapter::FillConvergenceTable(*pbd, output);
  }
}

//------------------------------------------------------------------------------
void vtkSoftBodyFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << this->Method << "\n";
  os << indent << "Device: " << this->Device << "\n";
  os << indent << "Integrator: " << this->Integrator << "\n";
  os << indent << "TimeStep: " << this->TimeStep << "\n";
  os << indent << "EndTime: " << this->EndTime << "\n";
  os << indent << "FrameInterval: " << this->FrameInterval << "\n";
  os << indent << "Gravity: " << this->Gravity[0] << " " << this->Gravity[1] << " "
     << this->Gravity[2] << "\n";
  os << indent << "Floor: " << this->Floor << "\n";
  os << indent << "FloorOrigin: " << this->FloorOrigin[0] << " " << this->FloorOrigin[1] << " "
     << this->FloorOrigin[2] << "\n";
  os << indent << "FloorNormal: " << this->FloorNormal[0] << " " << this->FloorNormal[1] << " "
     << this->FloorNormal[2] << "\n";
  os << indent << "PinnedPointsArray: "
     << (this->PinnedPointsArray.empty() ? "(none)" : this->PinnedPointsArray) << "\n";
  os << indent << "MaterialMode: " << this->MaterialMode << "\n";
  os << indent << "YoungsModulus: " << this->YoungsModulus << "\n";
  os << indent << "PoissonRatio: " << this->PoissonRatio << "\n";
  os << indent << "Density: " << this->Density << "\n";
  os << indent << "DampingTime: " << this->DampingTime << "\n";
  os << indent << "DistanceStiffness: " << this->DistanceStiffness << "\n";
  os << indent << "DistanceDamping: " << this->DistanceDamping << "\n";
  os << indent << "VolumeStiffness: " << this->VolumeStiffness << "\n";
  os << indent << "VolumeDamping: " << this->VolumeDamping << "\n";
  os << indent << "TotalMass: " << this->TotalMass << "\n";
  os << indent << "MassDistribution: " << this->MassDistribution << "\n";
  os << indent << "MaxInverseMass: " << this->MaxInverseMass << "\n";
  os << indent << "StrainLimit: " << this->StrainLimit << "\n";
  os << indent << "StrainLimitIterations: " << this->StrainLimitIterations << "\n";
  os << indent << "InvertedTets: " << this->InvertedTets << "\n";
  os << indent << "Solver: " << this->Solver << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "ResidualTolerance: " << this->ResidualTolerance << "\n";
  os << indent << "Relaxation: " << this->Relaxation << "\n";
  os << indent << "Substeps: " << this->Substeps << "\n";
  os << indent << "PBDLinkStiffness: " << this->PBDLinkStiffness << "\n";
  os << indent << "PBDVolumeStiffness: " << this->PBDVolumeStiffness << "\n";
  os << indent << "PBDPinStiffness: " << this->PBDPinStiffness << "\n";
  os << indent << "XPBDLinkCompliance: " << this->XPBDLinkCompliance << "\n";
  os << indent << "XPBDVolumeCompliance: " << this->XPBDVolumeCompliance << "\n";
  os << indent << "XPBDPinCompliance: " << this->XPBDPinCompliance << "\n";
  os << indent << "XPBDMaterial: " << this->XPBDMaterial << "\n";
  os << indent << "BreakingStrain: " << this->BreakingStrain << "\n";
  os << indent << "PlasticYield: " << this->PlasticYield << "\n";
  os << indent << "PlasticCreep: " << this->PlasticCreep << "\n";
  os << indent << "Friction: " << this->Friction << "\n";
  os << indent << "Restitution: " << this->Restitution << "\n";
  os << indent << "VelocityDamping: " << this->VelocityDamping << "\n";
  os << indent << "CacheMemoryLimit: " << this->CacheMemoryLimit << " MiB\n";
  os << indent << "SimulatedStepsTotal: " << this->SimulatedStepsTotal << "\n";
  os << indent << "CachedFrames: " << this->Internals->Cache.GetNumberOfFrames() << " ("
     << this->Internals->Cache.GetMemoryUsed() << " bytes)\n";
}
