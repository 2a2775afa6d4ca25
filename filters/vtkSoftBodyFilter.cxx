#include "vtkSoftBodyFilter.h"

#include "vtkSoftBodyArrays.h"
#include "vtkSoftBodyDistribution.h"
#include "vtkSoftBodyFloorOutput.h"
#include "vtkSoftBodyFrameCache.h"
#include "vtkSoftBodyImplicitReport.h"
#include "vtkSoftBodyInversionReport.h"
#include "vtkSoftBodyInputConversion.h"
#include "vtkSoftBodyObstacleInput.h"
#include "vtkSoftBodyPbdAdapter.h"
#include "vtkSoftBodySettings.h"
#include "vtkSoftBodySkin.h"
#include "vtkSoftBodySurfaceInput.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDemandDrivenPipeline.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkInformationExecutivePortKey.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLogger.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/common/errors.h"
#include "softbody/common/stepping.h"
#include "softbody/massspring/mass_spring_reordered.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/reorder.h"
#ifdef SOFTBODY_WITH_GPU
#include "softbody/gpu/mass_spring_gpu_simulation.h"
#endif

#include <algorithm>
#include <chrono>
#include <map>
#include <cmath>
#include <numeric>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkSoftBodyFilter);

using vtkSoftBodyArrays::MakeScalarArray;
using vtkSoftBodyArrays::MakeStringArray;
using vtkSoftBodyArrays::MakeVectorArray;

namespace
{
// Names of the devices in field data "Device" (the XML's enumeration texts).
constexpr const char* kDeviceNames[] = { "CPU", "GPU (EGL)" };

/// The GPU mass-spring stepper, or null with the reason why not (then the caller falls back
/// to the CPU). Invalid input throws InvalidInputError as the CPU stepper would.
std::unique_ptr<softbody::Simulation> MakeGpuSimulation(const softbody::BodyDescription& body,
  const softbody::SceneSettings& scene, std::string& renderer, std::string& whyNot)
{
#ifdef SOFTBODY_WITH_GPU
  // Built on the body renumbered for locality, like the CPU stepper (mass_spring_reordered.h),
  // with its floor where the CPU's contacts hold points (floorPassScene).
  const softbody::SceneSettings gpuScene = softbody::floorPassScene(body.mesh, scene);
  return softbody::buildReorderedMassSpring(body, gpuScene, softbody::kDefaultVertexOrdering,
    [&](softbody::BodyDescription stored) -> std::unique_ptr<softbody::Simulation> {
      std::unique_ptr<softbody::gpu::MassSpringGpuSimulation> simulation =
        softbody::gpu::tryCreateGpuMassSpring(stored, gpuScene, whyNot);
      if (simulation)
      {
        renderer = simulation->glRenderer();
      }
      return simulation;
    });
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
// One connection of the Obstacles input as far as the cache key is concerned: a static one by
// its surface (an equal surface from a re-executed source keeps the frames), a moving one by
// its producer's pipeline modification time (its surfaces change with the requested time,
// which does not modify the pipeline; a changed source parameter does).
struct vtkSoftBodyFilter::ObstacleConnection
{
  bool Moving = false;
  vtkMTimeType PipelineMTime = 0;  ///< moving ones only
  softbody::ObstacleSurface Static; ///< static ones only
  bool operator==(const ObstacleConnection&) const = default;
};

//------------------------------------------------------------------------------
// Run-time state kept between requests: the simulation, its frame cache and what they were
// built from.
class vtkSoftBodyFilter::vtkInternals
{
public:
  std::unique_ptr<softbody::Simulation> Simulation;
  /// Set when the simulation is PBD/XPBD: the solver inside `Simulation` (which maps its
  /// particles back to the input's order); its tet and link indices are the input's.
  softbody::PbdSimulation* Pbd = nullptr;
  vtkSoftBodyPbdAdapter PbdAdapter;
  /// The optional render surface's binding to the body (kept while both are unchanged).
  vtkSoftBodySkin Skin;
  vtkSoftBodyFrameCache Cache;
  /// Under MPI: this rank's whole bodies, gathered and dealt from the ranks' pieces.
  vtkSoftBodyDistribution Distribution;
  /// Grid frame the simulation's state is exactly at; -1 when between frames or unknown.
  int SimulationFrame = -1;

  // The cache key: which input (object and modification time) and which core settings the
  // simulation was built from.
  const vtkDataObject* Input = nullptr; // identity only, never dereferenced
  vtkMTimeType InputMTime = 0;
  vtkSoftBodyCoreSettings Settings;

  // The device the simulation runs on (may differ from the Device property after a fallback).
  int DeviceUsed = vtkSoftBodyFilter::DEVICE_CPU;
  std::string GLRenderer;
  std::string DeviceWarning; ///< why the GPU was not used although asked for; empty otherwise
  std::string RunWarning;     ///< the run to EndTime will take long (steps, time, remedies)
  std::string RunWarningSaid; ///< the last one printed, so it is said once
  bool InversionSaid = false; ///< inverted tets were warned of (once per simulation)

  /// The Obstacles input as the simulation was built with it (part of the cache key).
  std::vector<ObstacleConnection> Obstacles;
  /// Moving obstacles' surfaces by the time they were requested at (frame times and off-grid
  /// request times), one entry per connection (empty surfaces for static ones). Kept with
  /// the simulation: re-simulating an evicted frame needs the obstacles at its times again.
  std::map<double, std::vector<softbody::ObstacleSurface>> MovingObstaclesAt;
  /// The time the moving obstacles are requested at in the coming pass (time protocol).
  double ObstacleRequestTime = 0.0;

  /// The obstacle surfaces at time t, for the skinned Surface's correction: the static ones,
  /// and the moving ones as fetched for t (a moving one not fetched at t is left out).
  std::vector<softbody::ObstacleSurface> ObstaclesAt(double t, double tolerance) const
  {
    std::vector<softbody::ObstacleSurface> surfaces;
    // The fetch nearest to t (fetched at frame times k * FrameInterval, which a requested
    // time may differ from by rounding).
    auto moving = this->MovingObstaclesAt.lower_bound(t - tolerance);
    if (moving != this->MovingObstaclesAt.end() && std::abs(moving->first - t) > tolerance)
    {
      moving = this->MovingObstaclesAt.end();
    }
    for (std::size_t c = 0; c < this->Obstacles.size(); ++c)
    {
      if (!this->Obstacles[c].Moving)
      {
        surfaces.push_back(this->Obstacles[c].Static);
      }
      else if (moving != this->MovingObstaclesAt.end() && c < moving->second.size())
      {
        surfaces.push_back(moving->second[c]);
      }
    }
    return surfaces;
  }

  bool HasMovingObstacles() const
  {
    return std::any_of(this->Obstacles.begin(), this->Obstacles.end(),
      [](const ObstacleConnection& c) { return c.Moving; });
  }

  void Discard()
  {
    this->Simulation.reset();
    this->Pbd = nullptr;
    this->InversionSaid = false;
    this->Cache.Clear();
    this->SimulationFrame = -1;
    this->Input = nullptr;
    this->DeviceUsed = vtkSoftBodyFilter::DEVICE_CPU;
    this->GLRenderer.clear();
    this->DeviceWarning.clear();
    this->Obstacles.clear();
    this->MovingObstaclesAt.clear();
  }
};

//------------------------------------------------------------------------------
vtkSoftBodyFilter::vtkSoftBodyFilter()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(3);
  this->SetNumberOfOutputPorts(5);
  this->P = vtkSoftBodySettings::DefaultParameters();
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
    // The render surface to skin onto the body: optional. Any data object is accepted here so
    // that a wrong type gets one clear error (vtkSoftBodySurfaceInput) instead of the
    // executive's repeated type errors.
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    return 1;
  }
  if (port == 2)
  {
    // Obstacles: any number of connections; any data object, so a composite dataset gets
    // one clear error (vtkSoftBodyObstacleInput::TypeError).
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
}

//------------------------------------------------------------------------------
int vtkSoftBodyFilter::FillOutputPortInformation(int port, vtkInformation* info)
{
  const char* types[] = { "vtkUnstructuredGrid", "vtkPolyData", "vtkTable", "vtkPolyData",
    "vtkPolyData" };
  info->Set(vtkDataObject::DATA_TYPE_NAME(), types[std::min(port, 4)]);
  return 1;
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
  try
  {
    vtkSoftBodySettings::ValidateTimes(this->P);
  }
  catch (const softbody::InvalidInputError&)
  {
    // RequestData reports it; advertising no times keeps the pipeline sane meanwhile.
    return 1;
  }
  const std::vector<double> times = vtkSoftBodyFrameGrid{ this->P.FrameInterval, this->P.EndTime }.Times();
  const double range[2] = { 0.0, this->P.EndTime };
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
namespace
{
/// Asks an input for all of its data (piece 0 of 1, no ghosts), whatever piece this process
/// or this streamed pass is for.
void RequestWholeData(vtkInformation* inInfo)
{
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
}
} // namespace

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
  // Under MPI the Surface is skinned whole on rank 0, which then simulates every body
  // (RequestData): every rank asks for all of it, not the piece its number would select.
  vtkInformation* surfaceInfo = inputVector[1]->GetInformationObject(0);
  if (surfaceInfo && vtkSoftBodyDistribution::ParallelController())
  {
    RequestWholeData(surfaceInfo);
  }
  // A moving obstacle is asked for at the time the simulation needs next (RequestData names it
  // and asks the executive to run again: CONTINUE_EXECUTING), not at the time asked of us;
  // static ones get no time, so they never re-execute. Every rank under MPI (and every piece of
  // a streamed run) meets the whole obstacle, not the piece of it its own number would select.
  for (int c = 0; c < inputVector[2]->GetNumberOfInformationObjects(); ++c)
  {
    vtkInformation* inInfo = inputVector[2]->GetInformationObject(c);
    RequestWholeData(inInfo);
    if (vtkSoftBodyObstacleInput::IsTemporal(inInfo))
    {
      inInfo->Set(
        vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP(), this->Internals->ObstacleRequestTime);
    }
    else
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
  vtkPolyData* floorOutput = vtkPolyData::GetData(outputVector, 4);
  vtkDataObject* surfaceInput = vtkDataObject::GetData(inputVector[1], 0); // optional
  // A run that stopped to fetch a moving obstacle asked to be executed again; this one decides
  // afresh whether it needs another.
  request->Remove(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING());
  if (!input || !mesh || !particles || !convergence || !skinned || !floorOutput)
  {
    vtkErrorMacro("Missing input or output data object.");
    return 0;
  }
  const std::string surfaceError = vtkSoftBodySurfaceInput::SkinSurfaceError(surfaceInput);
  if (!surfaceError.empty())
  {
    vtkErrorMacro(<< surfaceError);
    return 0;
  }
  vtkPolyData* surface = vtkPolyData::SafeDownCast(surfaceInput);

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

  // Validate: the properties become core settings, refused with the user's value. The cache
  // stays on a refusal: correcting the value back finds it still valid.
  vtkSoftBodyCoreSettings settings;
  try
  {
    settings = vtkSoftBodySettings::Convert(this->P);
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  t = std::isnan(t) ? 0.0 : std::min(std::max(t, 0.0), this->P.EndTime);

  auto stampTime = [&]() {
    for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
    {
      vtkDataObject::GetData(outputVector, port)
        ->GetInformation()
        ->Set(vtkDataObject::DATA_TIME_STEP(), t);
    }
  };

  // Under MPI each rank simulates whole bodies: the pieces are gathered into bodies and the
  // bodies dealt to the ranks (vtkSoftBodyDistribution; every rank takes part). A rank without
  // a body outputs nothing, quietly. Bodies that collide with each other stay on one rank.
  if (vtkMultiProcessController* controller = vtkSoftBodyDistribution::ParallelController())
  {
    // Bodies that meet each other, or a Surface skinned onto them (rank 0 takes the whole
    // Surface, RequestUpdateExtent, and binds it to every body as the serial run does).
    const bool bodiesCollide = BodiesCollide(settings);
    const bool surfaceConnected = inputVector[1]->GetNumberOfInformationObjects() > 0;
    const bool together = bodiesCollide || surfaceConnected;
    vtkSoftBodyDistribution& distribution = this->Internals->Distribution;
    input = distribution.LocalBodies(input, controller, together);
    if (together && distribution.Redistributed() && distribution.GetNumberOfBodies() > 1 &&
      controller->GetLocalProcessId() == 0)
    {
      vtkWarningMacro(<< (bodiesCollide ? "Collisions include bodies, which must meet each other"
                                        : "A Surface is skinned onto the bodies")
                      << ": all " << distribution.GetNumberOfBodies()
                      << " bodies are simulated on rank 0 of " << controller->GetNumberOfProcesses()
                      << (bodiesCollide ? ". Set Collisions to Obstacles to spread them over the ranks."
                                        : ". Disconnect the Surface to spread them over the ranks."));
    }
    if (input->GetNumberOfCells() == 0)
    {
      stampTime();
      return 1;
    }
  }
  // Pieces streamed in one process (no MPI): an empty piece is normal and outputs nothing.
  else if ((input->GetNumberOfPoints() == 0 || input->GetNumberOfCells() == 0) &&
    requestInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) > 1)
  {
    stampTime();
    return 1;
  }

  // The Obstacles input (ignored with Collisions Off): each connection's key, and the moving
  // ones' surfaces at the time this pass requested them.
  std::vector<ObstacleConnection> obstacles;
  std::vector<softbody::ObstacleSurface> movingNow;
  if (this->CollisionsOn(settings))
  {
    const int count = inputVector[2]->GetNumberOfInformationObjects();
    for (int c = 0; c < count; ++c)
    {
      vtkInformation* info = inputVector[2]->GetInformationObject(c);
      vtkDataObject* object = info->Get(vtkDataObject::DATA_OBJECT());
      const std::string typeError = vtkSoftBodyObstacleInput::TypeError(object);
      if (!typeError.empty())
      {
        vtkErrorMacro(<< "Obstacles input " << c << ": " << typeError);
        return 0;
      }
      ObstacleConnection connection;
      connection.Moving = vtkSoftBodyObstacleInput::IsTemporal(info);
      if (connection.Moving)
      {
        auto* producer = vtkDemandDrivenPipeline::SafeDownCast(vtkExecutive::PRODUCER()->GetExecutive(info));
        connection.PipelineMTime = producer ? producer->GetPipelineMTime() : 0;
        movingNow.push_back(vtkSoftBodyObstacleInput::ToObstacle(object));
      }
      else
      {
        connection.Static = vtkSoftBodyObstacleInput::ToObstacle(object);
        movingNow.emplace_back();
      }
      obstacles.push_back(std::move(connection));
    }
  }

  // Compute. Core reports unusable input and divergence by exceptions; they must not cross
  // into the pipeline, and a simulation that threw is not trusted again. A refusal while
  // building a new simulation (core validates the settings then) leaves the current one and
  // its cache untouched (PrepareSimulation builds before it replaces): they are kept.
  bool prepared = false;
  try
  {
    if (!this->PrepareSimulation(input, settings, obstacles))
    {
      return 0;
    }
    prepared = true;
    if (this->Internals->HasMovingObstacles())
    {
      this->Internals->MovingObstaclesAt[this->Internals->ObstacleRequestTime] = std::move(movingNow);
    }
    // Said before a long run starts (and again only if EndTime or the simulation changes it).
    this->Internals->RunWarning = this->Internals->Simulation->longRunWarning(this->P.EndTime);
    if (!this->Internals->RunWarning.empty() &&
      this->Internals->RunWarning != this->Internals->RunWarningSaid)
    {
      vtkWarningMacro(<< this->Internals->RunWarning);
      this->Internals->RunWarningSaid = this->Internals->RunWarning;
    }
    const AdvanceResult advanced = this->AdvanceTo(t);
    if (advanced == AdvanceResult::Aborted)
    {
      // Aborted: CheckAbort has flagged the outputs; the executive empties them.
      return 1;
    }
    if (advanced == AdvanceResult::NeedsObstacles)
    {
      // The frames so far are cached; the executive runs the pipeline again with the moving
      // obstacles requested at ObstacleRequestTime (RequestUpdateExtent) and this request
      // resumes where it stopped. Outputs are filled by the pass that reaches `t`.
      request->Set(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING(), 1);
      return 1;
    }
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    if (prepared)
    {
      this->Internals->Discard();
    }
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
    if (prepared)
    {
      this->Internals->Discard();
    }
    return 0;
  }

  // Assemble the outputs. The surface is bound first: binding may warn (Warnings field data).
  if (surface)
  {
    const std::string skinError = this->Internals->Skin.Bind(input, surface);
    if (!skinError.empty())
    {
      vtkErrorMacro(<< "Cannot skin the Surface input onto the body: " << skinError);
      return 0;
    }
  }
  this->FillMesh(input, mesh, surface != nullptr);
  this->FillParticles(mesh, particles);
  this->FillConvergence(convergence);
  if (surface)
  {
    softbody::FloorPlane floor;
    floor.origin = softbody::Vec3(this->P.FloorOrigin[0], this->P.FloorOrigin[1], this->P.FloorOrigin[2]);
    floor.normal = softbody::Vec3(this->P.FloorNormal[0], this->P.FloorNormal[1], this->P.FloorNormal[2]);
    this->Internals->Skin.Fill(surface, this->Internals->Simulation->positions(), skinned,
      this->P.Floor != 0 ? &floor : nullptr, this->Internals->ObstaclesAt(this->Internals->Simulation->time(), 1e-6 * this->P.FrameInterval));
  }
  vtkSoftBodyFloorOutput::Fill(
    this->P.Floor != 0, this->P.FloorOrigin, this->P.FloorNormal, input->GetBounds(), floorOutput);
  stampTime();
  return 1;
}

//------------------------------------------------------------------------------
bool vtkSoftBodyFilter::PrepareSimulation(vtkUnstructuredGrid* input,
  const vtkSoftBodyCoreSettings& settings, const std::vector<ObstacleConnection>& obstacles)
{
  vtkInternals& internals = *this->Internals;
  internals.Cache.SetMemoryLimit(static_cast<std::size_t>(this->P.CacheMemoryLimit) << 20);

  // The key is what the simulation is built from; EndTime and CacheMemoryLimit are not part
  // of it, nor is any property the method ignores, so changing those keeps the cache.
  if (internals.Simulation && internals.Input == input &&
    internals.InputMTime == input->GetMTime() && internals.Settings == settings &&
    internals.Obstacles == obstacles)
  {
    return true;
  }

  // Build the new simulation aside and discard the current one only once that succeeded.
  // Core validates the settings (and the input) while it builds, so a value it refuses throws
  // here; discarding first lost every cached frame on such a refusal, and putting the value
  // back then simulated everything again (found by python.soak).
  vtkInternals built;
  if (settings.Method == PBD || settings.Method == XPBD)
  {
    std::string error;
    built.Simulation = built.PbdAdapter.Create(settings, input, error, built.Pbd);
    if (!built.Simulation)
    {
      vtkErrorMacro(<< error);
      return false;
    }
  }
  else if (!this->CreateMassSpring(input, settings, !obstacles.empty(), built))
  {
    return false;
  }
  // Static obstacles are set once (they are not part of the state the cache restores);
  // moving ones before every frame (AdvanceTo). Throws InvalidInputError for a method that
  // cannot collide with obstacles or a bad surface: the current simulation stays.
  built.Obstacles = obstacles;
  if (!obstacles.empty() && !built.HasMovingObstacles())
  {
    std::vector<softbody::ObstacleSurface> surfaces;
    for (const ObstacleConnection& connection : obstacles)
    {
      surfaces.push_back(connection.Static);
    }
    built.Simulation->setObstacles(std::move(surfaces), 0.0);
  }
  internals.Discard();
  internals.Simulation = std::move(built.Simulation);
  internals.Pbd = built.Pbd;
  internals.PbdAdapter = std::move(built.PbdAdapter);
  internals.DeviceUsed = built.DeviceUsed;
  internals.GLRenderer = std::move(built.GLRenderer);
  internals.DeviceWarning = std::move(built.DeviceWarning);
  internals.Obstacles = std::move(built.Obstacles);
  internals.Cache.Insert(0, internals.Simulation->state());
  internals.SimulationFrame = 0;
  internals.Input = input;
  internals.InputMTime = input->GetMTime();
  internals.Settings = settings;

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
bool vtkSoftBodyFilter::CreateMassSpring(vtkUnstructuredGrid* input,
  const vtkSoftBodyCoreSettings& settings, bool withObstacles, vtkInternals& built)
{
  softbody::BodyDescription body;
  const std::string inputError =
    vtkSoftBodyInputConversion::Convert(input, settings.PinnedPointsArray, body);
  if (!inputError.empty())
  {
    vtkErrorMacro(<< inputError);
    return false;
  }
  body.material = settings.Material;

  // Throws InvalidInputError for bad geometry or material; the caller reports it.
  // The GPU stepper collides with the floor only (like the implicit integrators' fallback,
  // the CPU runs what the GPU cannot, and says so).
  const softbody::CollisionMode mode = settings.Scene.collisions.mode;
  if (settings.Device == DEVICE_GPU_EGL &&
    (withObstacles || mode == softbody::CollisionMode::ObstaclesAndBodies ||
      mode == softbody::CollisionMode::ObstaclesBodiesAndSelf))
  {
    built.DeviceWarning = std::string("Device GPU (EGL) collides with the floor only, simulating "
                                      "on the CPU: ") +
      (withObstacles ? "an Obstacles input is connected" : "Collisions includes bodies") +
      " (set Collisions to Obstacles and disconnect the Obstacles to run on the GPU).";
    vtkWarningMacro(<< built.DeviceWarning);
  }
  else if (settings.Device == DEVICE_GPU_EGL)
  {
    std::string whyNot;
    built.Simulation = MakeGpuSimulation(body, settings.Scene, built.GLRenderer, whyNot);
    if (built.Simulation)
    {
      built.DeviceUsed = DEVICE_GPU_EGL;
      const softbody::CollisionSettings& c = settings.Scene.collisions;
      if (settings.Scene.floorEnabled &&
        (c.staticFriction > 0.0 || c.dynamicFriction > 0.0 || c.restitution > 0.0))
      {
        built.DeviceWarning = "Device GPU (EGL): the GPU's floor is frictionless and inelastic; "
                              "StaticFriction, DynamicFriction and Restitution act on the CPU "
                              "only (set them to 0 to silence this, or use Device CPU).";
        vtkWarningMacro(<< built.DeviceWarning);
      }
    }
    else
    {
      built.DeviceWarning = "Device GPU (EGL) is unavailable, simulating on the CPU: " + whyNot;
      vtkWarningMacro(<< built.DeviceWarning);
    }
  }
  if (!built.Simulation)
  {
    // Vertices renumbered along a space-filling curve, outputs in the input's order.
    built.Simulation = softbody::makeMassSpringSimulation(std::move(body), settings.Scene);
  }
  return true;
}

//------------------------------------------------------------------------------
vtkSoftBodyFilter::AdvanceResult vtkSoftBodyFilter::AdvanceTo(double t)
{
  vtkInternals& internals = *this->Internals;
  softbody::Simulation& simulation = *internals.Simulation;
  const vtkSoftBodyFrameGrid grid{ this->P.FrameInterval, this->P.EndTime };
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
    return AdvanceResult::Done;
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

  // Moving obstacles over [t0, t1]: their surfaces at t1 with the velocity from t0 (both
  // fetched by earlier passes); false, with the missing time to request, when one is not here.
  auto setMovingObstacles = [&](double t0, double t1) {
    if (!internals.HasMovingObstacles())
    {
      return true;
    }
    const auto start = internals.MovingObstaclesAt.find(t0);
    const auto end = internals.MovingObstaclesAt.find(t1);
    if (start == internals.MovingObstaclesAt.end() || end == internals.MovingObstaclesAt.end())
    {
      internals.ObstacleRequestTime = start == internals.MovingObstaclesAt.end() ? t0 : t1;
      return false;
    }
    std::vector<softbody::ObstacleSurface> surfaces;
    for (std::size_t c = 0; c < internals.Obstacles.size(); ++c)
    {
      const ObstacleConnection& connection = internals.Obstacles[c];
      surfaces.push_back(connection.Moving
          ? vtkSoftBodyObstacleInput::WithVelocities(end->second[c], start->second[c], t1 - t0)
          : connection.Static);
    }
    simulation.setObstacles(std::move(surfaces), t1);
    return true;
  };

  auto runTo = [&](double endTime) {
    const unsigned long long before = simulation.stepCount();
    const softbody::AdvanceStatus status = simulation.advance(endTime, progress);
    this->SimulatedStepsTotal += simulation.stepCount() - before;
    return status == softbody::AdvanceStatus::Completed && !aborted;
  };

  // A run announced as long also says, in the log (visible in pvpython, where no progress bar
  // is), how far it got and how long the rest will take: at most one line every 10 s.
  const auto started = std::chrono::steady_clock::now();
  auto lastLog = started;
  auto logLongRunProgress = [&](int frame) {
    const auto now = std::chrono::steady_clock::now();
    if (internals.RunWarning.empty() || now - lastLog < std::chrono::seconds(10))
    {
      return;
    }
    lastLog = now;
    const double elapsed = std::chrono::duration<double>(now - started).count();
    const double left = elapsed / framesDone * (framesToRun - framesDone);
    vtkLogF(INFO, "Soft Body: frame %d of %d simulated (t = %g s) in %.0f s; about %.0f s to go.",
      frame, target, frame * this->P.FrameInterval, elapsed, left);
  };
  for (int k = first + 1; k <= target; ++k)
  {
    if (!setMovingObstacles((k - 1) * this->P.FrameInterval, k * this->P.FrameInterval))
    {
      return AdvanceResult::NeedsObstacles; // still exactly at frame k - 1
    }
    if (this->CheckAbort() || !runTo(k * this->P.FrameInterval))
    {
      internals.SimulationFrame = -1; // stopped somewhere inside frame k
      return AdvanceResult::Aborted;
    }
    internals.SimulationFrame = k;
    internals.Cache.Insert(k, simulation.state());
    ++framesDone;
    logLongRunProgress(k);
  }
  if (!onGrid)
  {
    // Off-grid times (only EndTime, or a time a script asks for) are not cached: the next
    // request resumes from the grid frame before them.
    if (!setMovingObstacles(target * this->P.FrameInterval, t))
    {
      return AdvanceResult::NeedsObstacles;
    }
    internals.SimulationFrame = -1;
    if (this->CheckAbort() || !runTo(t))
    {
      return AdvanceResult::Aborted;
    }
  }
  this->UpdateProgress(1.0);
  return AdvanceResult::Done;
}

//------------------------------------------------------------------------------
bool vtkSoftBodyFilter::CollisionsOn(const vtkSoftBodyCoreSettings& settings)
{
  const softbody::CollisionSettings& collisions =
    settings.Method == MASS_SPRING ? settings.Scene.collisions : settings.Pbd.collisions;
  return collisions.mode != softbody::CollisionMode::Off;
}

//------------------------------------------------------------------------------
bool vtkSoftBodyFilter::BodiesCollide(const vtkSoftBodyCoreSettings& settings)
{
  const softbody::CollisionMode mode =
    (settings.Method == MASS_SPRING ? settings.Scene.collisions : settings.Pbd.collisions).mode;
  return mode == softbody::CollisionMode::ObstaclesAndBodies ||
    mode == softbody::CollisionMode::ObstaclesBodiesAndSelf;
}

//------------------------------------------------------------------------------
double vtkSoftBodyFilter::StepUsed() const
{
  const softbody::Simulation& simulation = *this->Internals->Simulation;
  const double previous = simulation.state().previousStep;
  if (previous > 0.0)
  {
    return previous;
  }
  return this->P.FrameInterval /
    static_cast<double>(softbody::equalStepCount(this->P.FrameInterval, simulation.stepSize()));
}

//------------------------------------------------------------------------------
void vtkSoftBodyFilter::FillMesh(
  vtkUnstructuredGrid* input, vtkUnstructuredGrid* output, bool withSurface)
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
  // The active scalars are what ParaView colours a new representation by (speed, for a
  // 3-component array); without them Apply shows a solid colour. They replace any the input had.
  output->GetPointData()->SetActiveScalars("Velocity");

  // Core keeps the tets in input cell order, so the ratios map onto the input cells; a PBD
  // input that mixes tets with other cells maps them through the adapter (NaN for non-tets).
  std::vector<double> ratios = simulation.tetVolumeRatios();
  const std::size_t tetCount = ratios.size();
  const std::size_t inverted = vtkSoftBodyInversionReport::Count(ratios, this->Internals->Pbd);
  if (this->Internals->Pbd && !ratios.empty())
  {
    ratios = this->Internals->PbdAdapter.PerInputCell(ratios, input->GetNumberOfCells());
  }
  std::string inversionWarning;
  if (static_cast<vtkIdType>(ratios.size()) == input->GetNumberOfCells())
  {
    output->GetCellData()->AddArray(MakeScalarArray("VolumeRatio", ratios));
    vtkSoftBodyInversionReport::AddField(inverted, output->GetFieldData());
    inversionWarning = vtkSoftBodyInversionReport::Warning(
      inverted, tetCount, simulation.time(), this->P);
    if (!inversionWarning.empty() && !this->Internals->InversionSaid)
    {
      vtkWarningMacro(<< inversionWarning);
      this->Internals->InversionSaid = true;
    }
  }

  vtkFieldData* field = output->GetFieldData();
  field->AddArray(MakeScalarArray("SimulationTime", { simulation.time() }));
  auto steps = vtkSmartPointer<vtkIdTypeArray>::New();
  steps->SetName("StepCount");
  steps->InsertNextValue(static_cast<vtkIdType>(simulation.stepCount()));
  field->AddArray(steps);
  field->AddArray(MakeScalarArray("TimeStep", { this->StepUsed() }));
  field->AddArray(MakeScalarArray("StableTimeStep", { simulation.estimatedStableStep() }));
  field->AddArray(MakeScalarArray("TotalMass", { simulation.totalMass() }));

  field->AddArray(MakeStringArray(
    "Integrator", { softbody::integratorName(vtkSoftBodySettings::Integrator(this->P.Integrator)) }));
  if (const softbody::PbdSimulation* pbd = this->Internals->Pbd)
  {
    this->Internals->PbdAdapter.AddBrokenCells(*pbd, output);
    vtkSoftBodyPbdAdapter::AddConvergenceFields(*pbd, output);
  }
  const softbody::ImplicitConvergence* implicit = this->ImplicitSolveReport();
  if (implicit)
  {
    vtkSoftBodyImplicitReport::AddFields(*implicit, field);
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
  if (!this->Internals->RunWarning.empty())
  {
    warnings.push_back(this->Internals->RunWarning);
  }
  if (implicit)
  {
    const std::string unconverged = vtkSoftBodyImplicitReport::Warning(*implicit,
      softbody::integratorName(vtkSoftBodySettings::Integrator(this->P.Integrator)),
      this->P.ImplicitMaxIterations);
    if (!unconverged.empty())
    {
      warnings.push_back(unconverged);
    }
  }
  for (const std::string& warning : vtkSoftBodySettings::Warnings(this->P))
  {
    warnings.push_back(warning);
  }
  if (!inversionWarning.empty())
  {
    warnings.push_back(inversionWarning);
  }
  if (withSurface && !this->Internals->Skin.GetWarning().empty())
  {
    warnings.push_back(this->Internals->Skin.GetWarning());
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
  else if (const softbody::ImplicitConvergence* implicit = this->ImplicitSolveReport())
  {
    vtkSoftBodyImplicitReport::FillTable(*implicit, output);
  }
}

//------------------------------------------------------------------------------
const softbody::ImplicitConvergence* vtkSoftBodyFilter::ImplicitSolveReport() const
{
  // Only the CPU mass-spring stepper has implicit integrators (the GPU falls back to it); it
  // may sit inside the renumbering wrapper, and a residual history needs no renumbering.
  const softbody::Simulation* simulation = this->Internals->Simulation.get();
  if (const auto* reordered = dynamic_cast<const softbody::ReorderedSimulation*>(simulation))
  {
    simulation = &reordered->inner();
  }
  const auto* massSpring = dynamic_cast<const softbody::MassSpringSimulation*>(simulation);
  return massSpring ? massSpring->implicitConvergence() : nullptr;
}

//------------------------------------------------------------------------------
void vtkSoftBodyFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << this->P.Method << "\n";
  os << indent << "Device: " << this->P.Device << "\n";
  os << indent << "Integrator: " << this->P.Integrator << "\n";
  os << indent << "TimeStep: " << this->P.TimeStep << "\n";
  os << indent << "EndTime: " << this->P.EndTime << "\n";
  os << indent << "FrameInterval: " << this->P.FrameInterval << "\n";
  os << indent << "Gravity: " << this->P.Gravity[0] << " " << this->P.Gravity[1] << " "
     << this->P.Gravity[2] << "\n";
  os << indent << "Floor: " << this->P.Floor << "\n";
  os << indent << "FloorOrigin: " << this->P.FloorOrigin[0] << " " << this->P.FloorOrigin[1] << " "
     << this->P.FloorOrigin[2] << "\n";
  os << indent << "FloorNormal: " << this->P.FloorNormal[0] << " " << this->P.FloorNormal[1] << " "
     << this->P.FloorNormal[2] << "\n";
  os << indent << "PinnedPointsArray: "
     << (this->P.PinnedPointsArray.empty() ? "(none)" : this->P.PinnedPointsArray) << "\n";
  vtkSoftBodySettings::PrintMaterial(os, indent, this->P);
  os << indent << "MaxInverseMass: " << this->P.MaxInverseMass << "\n";
  os << indent << "StrainLimit: " << this->P.StrainLimit << "\n";
  os << indent << "StrainLimitIterations: " << this->P.StrainLimitIterations << "\n";
  os << indent << "InvertedTets: " << this->P.InvertedTets << "\n";
  os << indent << "Solver: " << this->P.Solver << "\n";
  os << indent << "Iterations: " << this->P.Iterations << "\n";
  os << indent << "ResidualTolerance: " << this->P.ResidualTolerance << "\n";
  os << indent << "Relaxation: " << this->P.Relaxation << "\n";
  os << indent << "Substeps: " << this->P.Substeps << "\n";
  os << indent << "PBDLinkStiffness: " << this->P.PBDLinkStiffness << "\n";
  os << indent << "PBDVolumeStiffness: " << this->P.PBDVolumeStiffness << "\n";
  os << indent << "PBDPinStiffness: " << this->P.PBDPinStiffness << "\n";
  os << indent << "XPBDLinkCompliance: " << this->P.XPBDLinkCompliance << "\n";
  os << indent << "XPBDVolumeCompliance: " << this->P.XPBDVolumeCompliance << "\n";
  os << indent << "XPBDPinCompliance: " << this->P.XPBDPinCompliance << "\n";
  os << indent << "XPBDMaterial: " << this->P.XPBDMaterial << "\n";
  os << indent << "BreakingStrain: " << this->P.BreakingStrain << "\n";
  os << indent << "PlasticYield: " << this->P.PlasticYield << "\n";
  os << indent << "PlasticCreep: " << this->P.PlasticCreep << "\n";
  os << indent << "Collisions: " << this->P.Collisions << "\n";
  os << indent << "BroadPhase: " << this->P.BroadPhase << "\n";
  os << indent << "CollisionMargin: " << this->P.CollisionMargin << "\n";
  os << indent << "StaticFriction: " << this->P.StaticFriction << "\n";
  os << indent << "DynamicFriction: " << this->P.DynamicFriction << "\n";
  os << indent << "Restitution: " << this->P.Restitution << "\n";
  os << indent << "VelocityDamping: " << this->P.VelocityDamping << "\n";
  os << indent << "CacheMemoryLimit: " << this->P.CacheMemoryLimit << " MiB\n";
  os << indent << "Obstacles: " << this->GetNumberOfInputConnections(2) << " connections\n";
  os << indent << "SimulatedStepsTotal: " << this->SimulatedStepsTotal << "\n";
  os << indent << "CachedFrames: " << this->Internals->Cache.GetNumberOfFrames() << " ("
     << this->Internals->Cache.GetMemoryUsed() << " bytes)\n";
}
