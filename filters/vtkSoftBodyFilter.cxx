#include "vtkSoftBodyFilter.h"

#include "vtkSoftBodyConditionCodec.h"
#include "vtkSoftBodyConditionInput.h"
#include "vtkSoftBodyArrays.h"
#include "vtkSoftBodyDistribution.h"
#include "vtkSoftBodyFloorPlacement.h"
#include "vtkSoftBodyMethodChoice.h"
#include "vtkSoftBodyFrameCache.h"
#include "vtkSoftBodyFrameRunner.h"
#include "vtkSoftBodyObstacleTimeline.h"
#include "vtkSoftBodyOutputAssembly.h"
#include "vtkSoftBodyOutputPort.h"
#include "vtkSoftBodySettings.h"
#include "vtkSoftBodySimulationFactory.h"
#include "vtkSoftBodySkin.h"
#include "vtkSoftBodySurfaceInput.h"

#include "vtkDemandDrivenPipeline.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/common/errors.h"

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkSoftBodyFilter);

//------------------------------------------------------------------------------
// Run-time state kept between requests (vtkSoftBodyFrameRunner: the simulation, its frame
// cache and what they were built from).
class vtkSoftBodyFilter::vtkInternals : public vtkSoftBodyFrameRunner
{
public:
  vtkSoftBodyConditionInput Conditions; ///< the Conditions input, converted on the body
  std::string FloorWarning;     ///< the floor was placed off FloorOrigin (vtkSoftBodyFloorPlacement)
  std::string FloorWarningSaid; ///< the last one printed, so it is said once
  /// The properties this pass runs with: the user's, with Method Automatic resolved.
  vtkSoftBodyParameters Resolved;
  std::string MethodNote;     ///< what Automatic chose, where it chose XPBD (vtkSoftBodyMethodChoice)
  std::string MethodNoteSaid; ///< the last one printed
};

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

/// The output information of the port the request came from: it holds the requested time
/// (another port may hold a stale request). Every output is produced for that time.
vtkInformation* RequestingPortInformation(
  vtkInformation* request, vtkInformationVector* outputVector)
{
  int fromPort = 0;
  if (request->Has(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()))
  {
    fromPort = std::max(0, request->Get(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()));
  }
  return outputVector->GetInformationObject(fromPort);
}
} // namespace

//------------------------------------------------------------------------------
vtkSoftBodyFilter::vtkSoftBodyFilter()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(4);
  this->SetNumberOfOutputPorts(vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Count));
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
  if (port == 2 || port == 3)
  {
    // Obstacles and Conditions: any number of connections; any data object, so a composite
    // dataset gets one clear error (vtkSoftBodyObstacleInput::TypeError,
    // vtkSoftBodyConditionInput).
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
  info->Set(vtkDataObject::DATA_TYPE_NAME(),
    vtkSoftBodyOutputAssembly::DataTypeName(static_cast<vtkSoftBodyOutputPort>(port)));
  return 1;
}

//------------------------------------------------------------------------------
int vtkSoftBodyFilter::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  // The filter makes its own time: whatever times the input advertised are replaced on every
  // port, so a static input does not limit the animation and a temporal one does not confuse it.
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
  // Conditions hold their own time functions: their producers are not asked for our time.
  for (int c = 0; c < inputVector[3]->GetNumberOfInformationObjects(); ++c)
  {
    inputVector[3]->GetInformationObject(c)->Remove(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  }
  // Under MPI the Surface is skinned whole on rank 0, which then simulates every body
  // (RequestData): every rank asks for all of it, not the piece its number would select.
  vtkInformation* surfaceInfo = inputVector[1]->GetInformationObject(0);
  if (surfaceInfo && vtkSoftBodyDistribution::ParallelController())
  {
    RequestWholeData(surfaceInfo);
  }
  // A moving obstacle is asked for at the time the simulation needs next, not at the time asked
  // of us (vtkSoftBodyObstacleTimeline); static ones get no time, so they never re-execute.
  // Every rank under MPI (and every piece of a streamed run) meets the whole obstacle, not the
  // piece of it its own number would select.
  for (int c = 0; c < inputVector[2]->GetNumberOfInformationObjects(); ++c)
  {
    vtkInformation* inInfo = inputVector[2]->GetInformationObject(c);
    RequestWholeData(inInfo);
    this->Internals->Obstacles.RequestTime(inInfo);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkSoftBodyFilter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkDataObject* surfaceInput = vtkDataObject::GetData(inputVector[1], 0); // optional
  const vtkSoftBodyOutputAssembly::Outputs outputs = vtkSoftBodyOutputAssembly::Fetch(outputVector);
  // A run that stopped to fetch a moving obstacle asked to be executed again; this one decides
  // afresh whether it needs another.
  request->Remove(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING());
  if (!input || !outputs.Complete())
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
  vtkInformation* requestInfo = RequestingPortInformation(request, outputVector);

  // A note made from the input is asked again on every time request: it is said once.
  const auto sayOnce = [this](const std::string& message, std::string& said) {
    if (!message.empty() && message != said)
    {
      vtkWarningMacro(<< message);
      said = message;
    }
  };

  // Method Automatic becomes the method the input's cells need (collective under MPI). The
  // user's properties stay as they were given; this pass runs with the resolved copy.
  vtkInternals& internals = *this->Internals;
  internals.Resolved = this->P;
  internals.Resolved.Method = vtkSoftBodyMethodChoice::Resolve(
    this->P.Method, input, vtkSoftBodyDistribution::ParallelController(), internals.MethodNote);
  sayOnce(internals.MethodNote, internals.MethodNoteSaid);

  // The properties become core settings, refused with the user's value. The cache stays on a
  // refusal: correcting the value back finds it still valid.
  vtkSoftBodyCoreSettings settings;
  try
  {
    settings = vtkSoftBodySettings::Convert(internals.Resolved);
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  const double t = this->RequestedTime(requestInfo);

  input = this->LocalInput(
    input, settings, inputVector[1]->GetNumberOfInformationObjects() > 0, requestInfo);
  // Where the floor goes, from the body (collective under MPI: before a rank without a body
  // returns). Part of the settings, so a body moved under the floor rebuilds the run.
  internals.FloorWarning = vtkSoftBodyFloorPlacement::Place(this->P.FloorPlacement, input,
    vtkSoftBodyDistribution::ParallelController(), settings.SelectedScene());
  sayOnce(internals.FloorWarning, internals.FloorWarningSaid);
  if (!input)
  {
    vtkSoftBodyOutputAssembly::StampTime(outputVector, t);
    return 1;
  }

  // The Conditions input, its sets found among this rank's body points; part of the settings
  // the simulation is built from, so a changed condition rebuilds it.
  const std::string conditionError =
    this->Internals->Conditions.Read(inputVector[3], input, settings.Conditions);
  if (!conditionError.empty())
  {
    vtkErrorMacro(<< conditionError);
    return 0;
  }
  for (const std::string& warning : this->Internals->Conditions.GetWarnings())
  {
    vtkWarningMacro(<< warning);
  }

  // The Obstacles input (ignored with Collisions Off): each connection's key, and the moving
  // ones' surfaces at the time this pass requested them.
  std::vector<vtkSoftBodyObstacleConnection> obstacles;
  std::vector<softbody::ObstacleSurface> deliveredNow;
  if (settings.SelectedScene().collisions.on())
  {
    const std::string obstacleError =
      vtkSoftBodyObstacleTimeline::Read(inputVector[2], obstacles, deliveredNow);
    if (!obstacleError.empty())
    {
      vtkErrorMacro(<< obstacleError);
      return 0;
    }
  }

  switch (this->Simulate(input, settings, obstacles, std::move(deliveredNow), t))
  {
    case vtkSoftBodyRunResult::Failed:
      return 0;
    case vtkSoftBodyRunResult::Aborted:
      // CheckAbort has flagged the outputs; the executive empties them.
      return 1;
    case vtkSoftBodyRunResult::NeedsObstacles:
      // The frames so far are cached; the executive runs the pipeline again with the moving
      // obstacles requested at the time they are needed (RequestUpdateExtent) and this request
      // resumes where it stopped. Outputs are filled by the pass that reaches `t`.
      request->Set(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING(), 1);
      return 1;
    case vtkSoftBodyRunResult::Done:
      break;
  }

  if (!this->AssembleOutputs(input, surface, outputs))
  {
    return 0;
  }
  vtkSoftBodyOutputAssembly::StampTime(outputVector, t);
  return 1;
}

//------------------------------------------------------------------------------
double vtkSoftBodyFilter::RequestedTime(vtkInformation* requestInfo) const
{
  double t = 0.0;
  if (requestInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    t = requestInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  }
  return std::isnan(t) ? 0.0 : std::min(std::max(t, 0.0), this->P.EndTime);
}

//------------------------------------------------------------------------------
vtkUnstructuredGrid* vtkSoftBodyFilter::LocalInput(vtkUnstructuredGrid* input,
  const vtkSoftBodyCoreSettings& settings, bool surfaceConnected, vtkInformation* requestInfo)
{
  // Under MPI each rank simulates whole bodies: the pieces are gathered into bodies and the
  // bodies dealt to the ranks (vtkSoftBodyDistribution; every rank takes part). A rank without
  // a body outputs nothing, quietly. Bodies that collide with each other stay on one rank.
  if (vtkMultiProcessController* controller = vtkSoftBodyDistribution::ParallelController())
  {
    // Bodies that meet each other, or a Surface skinned onto them (rank 0 takes the whole
    // Surface, RequestUpdateExtent, and binds it to every body as the serial run does).
    const bool bodiesCollide = settings.SelectedScene().collisions.bodiesCollide();
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
    return input->GetNumberOfCells() == 0 ? nullptr : input;
  }
  // Pieces streamed in one process (no MPI): an empty piece is normal and outputs nothing.
  if ((input->GetNumberOfPoints() == 0 || input->GetNumberOfCells() == 0) &&
    requestInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) > 1)
  {
    return nullptr;
  }
  return input;
}

//------------------------------------------------------------------------------
vtkSoftBodyRunResult vtkSoftBodyFilter::Simulate(vtkUnstructuredGrid* input,
  const vtkSoftBodyCoreSettings& settings,
  const std::vector<vtkSoftBodyObstacleConnection>& obstacles,
  std::vector<softbody::ObstacleSurface> deliveredNow, double t)
{
  vtkSoftBodyFrameRunner::Hooks hooks;
  hooks.Warn = [this](const std::string& message) { vtkWarningMacro(<< message); };
  hooks.Error = [this](const std::string& message) { vtkErrorMacro(<< message); };
  hooks.Progress = [this](double fraction) { this->UpdateProgress(fraction); };
  hooks.Abort = [this] { return this->CheckAbort(); };
  return this->Internals->Simulate(input, settings, obstacles, std::move(deliveredNow), t,
    this->Internals->Resolved, hooks, this->SimulatedStepsTotal);
}

//------------------------------------------------------------------------------
bool vtkSoftBodyFilter::AssembleOutputs(vtkUnstructuredGrid* input, vtkPolyData* surface,
  const vtkSoftBodyOutputAssembly::Outputs& outputs)
{
  vtkInternals& internals = *this->Internals;
  // The surface is bound first: binding may warn (Warnings field data).
  if (surface)
  {
    const std::string skinError = internals.Skin.Bind(input, surface);
    if (!skinError.empty())
    {
      vtkErrorMacro(<< "Cannot skin the Surface input onto the body: " << skinError);
      return false;
    }
  }
  const std::string inversionWarning = vtkSoftBodyOutputAssembly::FillMesh(input, internals.Built,
    internals.Resolved, { internals.MethodNote, internals.FloorWarning, internals.RunWarning, internals.LandingWarning }, surface ? internals.Skin.GetWarning() : std::string(),
    outputs.Mesh);
  if (!inversionWarning.empty() && !internals.InversionSaid)
  {
    vtkWarningMacro(<< inversionWarning);
    internals.InversionSaid = true;
  }
  // When the conditions were changed during playback, and from which frames on.
  const std::vector<double> changes = internals.ConditionChangeTimes(internals.Resolved.FrameInterval);
  if (!changes.empty())
  {
    vtkNew<vtkDoubleArray> times;
    times->SetName("ConditionChangeTimes");
    for (double time : changes)
    {
      times->InsertNextValue(time);
    }
    outputs.Mesh->GetFieldData()->AddArray(times);
    vtkSoftBodyConditionCodec::EncodeValuesOverTheRun(internals.ConditionValuesOverTheRun(),
      outputs.Mesh->GetFieldData());
  }
  vtkSoftBodyOutputAssembly::FillParticles(internals.Built, outputs.Mesh, outputs.Particles);
  vtkSoftBodyOutputAssembly::FillConvergence(internals.Built, outputs.Convergence);
  if (surface)
  {
    vtkSoftBodyOutputAssembly::FillSurface(internals.Skin, surface, internals.Built,
      internals.BuiltSettings().SelectedScene(),
      internals.Obstacles.At(internals.Built.Simulation->time(), 1e-6 * internals.Resolved.FrameInterval),
      outputs.Surface);
  }
  vtkSoftBodyOutputAssembly::FillFloor(internals.Resolved, internals.BuiltSettings().SelectedScene(), input, outputs);
  outputs.Mesh->GetFieldData()->AddArray(vtkSoftBodyArrays::MakeStringArray(
    "Method", { vtkSoftBodyMethodChoice::Name(internals.Resolved.Method) }));
  const double shown = internals.Built.Simulation->time();
  internals.Timings.FillTable(shown, outputs.Timings);
  internals.Timings.AddFields(shown, outputs.Mesh->GetFieldData());
  return true;
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
  os << indent << "FloorPlacement: " << this->P.FloorPlacement << "\n";
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
  os << indent << "Conditions: " << this->GetNumberOfInputConnections(3) << " connections\n";
  os << indent << "SimulatedStepsTotal: " << this->SimulatedStepsTotal << "\n";
  os << indent << "CachedFrames: " << this->Internals->Cache.GetNumberOfFrames() << " ("
     << this->Internals->Cache.GetMemoryUsed() << " bytes)\n";
}
