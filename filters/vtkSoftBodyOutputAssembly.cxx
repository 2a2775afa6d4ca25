#include "vtkSoftBodyOutputAssembly.h"

#include "vtkSoftBodyArrays.h"
#include "vtkSoftBodyFloorOutput.h"
#include "vtkSoftBodyImplicitReport.h"
#include "vtkSoftBodyInversionReport.h"
#include "vtkSoftBodyParameters.h"
#include "vtkSoftBodyPbdAdapter.h"
#include "vtkSoftBodySettings.h"
#include "vtkSoftBodySimulationFactory.h"
#include "vtkSoftBodySkin.h"
#include "vtkSoftBodyConditionOutput.h"
#include "vtkSoftBodyStressOutput.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/common/floor_plane.h"
#include "softbody/common/stepping.h"
#include "softbody/massspring/mass_spring_reordered.h"
#include "softbody/massspring/mass_spring_simulation.h"

#include <cmath>
#include <numeric>

using vtkSoftBodyArrays::MakeScalarArray;
using vtkSoftBodyArrays::MakeStringArray;
using vtkSoftBodyArrays::MakeVectorArray;

namespace
{
// Names of the devices in field data "Device" (the XML's enumeration texts).
constexpr const char* kDeviceNames[] = { "CPU", "GPU (EGL)" };

vtkSmartPointer<vtkPoints> MakePoints(const std::vector<softbody::Vec3>& positions)
{
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(MakeVectorArray("Points", positions));
  return points;
}

/// The step the simulation takes: the frame interval split into equal steps no larger than
/// its step size (what the last advance used; before any, what the frames will use).
double StepUsed(const softbody::Simulation& simulation, double frameInterval)
{
  const double previous = simulation.state().previousStep;
  if (previous > 0.0)
  {
    return previous;
  }
  return frameInterval /
    static_cast<double>(softbody::equalStepCount(frameInterval, simulation.stepSize()));
}

/// The CPU mass-spring stepper; null for PBD and the GPU. It may sit inside the renumbering
/// wrapper; what is read from it here (solve and step reports) needs no renumbering.
const softbody::MassSpringSimulation* CpuMassSpring(const vtkSoftBodyBuiltSimulation& built)
{
  const softbody::Simulation* simulation = built.Simulation.get();
  if (const auto* reordered = dynamic_cast<const softbody::ReorderedSimulation*>(simulation))
  {
    simulation = &reordered->inner();
  }
  return dynamic_cast<const softbody::MassSpringSimulation*>(simulation);
}

/// The implicit integrators' solve report; null for explicit integrators and PBD.
const softbody::ImplicitConvergence* ImplicitSolveReport(const vtkSoftBodyBuiltSimulation& built)
{
  // Only the CPU mass-spring stepper has implicit integrators (the GPU falls back to it).
  const softbody::MassSpringSimulation* massSpring = CpuMassSpring(built);
  return massSpring ? massSpring->implicitConvergence() : nullptr;
}

/// Error-controlled steps: what the controller did to reach this frame.
void AddStepControlFields(const softbody::StepControlReport& report, vtkFieldData* field)
{
  const auto count = [&](const char* name, unsigned long long value) {
    auto array = vtkSmartPointer<vtkIdTypeArray>::New();
    array->SetName(name);
    array->InsertNextValue(static_cast<vtkIdType>(value));
    field->AddArray(array);
  };
  count("AcceptedSteps", report.acceptedSteps);
  count("RejectedSteps", report.rejectedSteps);
  count("StepsOverTolerance", report.stepsOverTolerance);
  count("EventSteps", report.eventSteps);
  field->AddArray(MakeScalarArray("EstimatedError", { report.estimatedError }));
  field->AddArray(MakeScalarArray("SmallestStep", { report.smallestStep }));
  field->AddArray(MakeScalarArray("LargestStep", { report.largestStep }));
}
} // namespace

//------------------------------------------------------------------------------
bool vtkSoftBodyOutputAssembly::Outputs::Complete() const
{
  return this->Mesh && this->Particles && this->Convergence && this->Surface && this->Floor &&
    this->Timings;
}

//------------------------------------------------------------------------------
const char* vtkSoftBodyOutputAssembly::DataTypeName(vtkSoftBodyOutputPort port)
{
  switch (port)
  {
    case vtkSoftBodyOutputPort::Mesh:
      return "vtkUnstructuredGrid";
    case vtkSoftBodyOutputPort::Convergence:
    case vtkSoftBodyOutputPort::Timings:
      return "vtkTable";
    default:
      return "vtkPolyData";
  }
}

//------------------------------------------------------------------------------
vtkSoftBodyOutputAssembly::Outputs vtkSoftBodyOutputAssembly::Fetch(
  vtkInformationVector* outputVector)
{
  Outputs outputs;
  outputs.Mesh =
    vtkUnstructuredGrid::GetData(outputVector, vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Mesh));
  outputs.Particles =
    vtkPolyData::GetData(outputVector, vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Particles));
  outputs.Convergence =
    vtkTable::GetData(outputVector, vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Convergence));
  outputs.Surface =
    vtkPolyData::GetData(outputVector, vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Surface));
  outputs.Floor =
    vtkPolyData::GetData(outputVector, vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Floor));
  outputs.Timings =
    vtkTable::GetData(outputVector, vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Timings));
  return outputs;
}

//------------------------------------------------------------------------------
void vtkSoftBodyOutputAssembly::StampTime(vtkInformationVector* outputVector, double t)
{
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkDataObject::GetData(outputVector, port)
      ->GetInformation()
      ->Set(vtkDataObject::DATA_TIME_STEP(), t);
  }
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyOutputAssembly::FillMesh(vtkUnstructuredGrid* input,
  const vtkSoftBodyBuiltSimulation& built, const vtkSoftBodyParameters& p,
  const std::vector<std::string>& beforeRun, const std::string& surfaceWarning, vtkUnstructuredGrid* output)
{
  const softbody::Simulation& simulation = *built.Simulation;

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
  const std::size_t inverted = vtkSoftBodyInversionReport::Count(ratios, built.Pbd);
  if (built.Pbd && !ratios.empty())
  {
    ratios = built.PbdAdapter.PerInputCell(ratios, input->GetNumberOfCells());
  }
  std::string inversionWarning;
  if (static_cast<vtkIdType>(ratios.size()) == input->GetNumberOfCells())
  {
    output->GetCellData()->AddArray(MakeScalarArray("VolumeRatio", ratios));
    vtkSoftBodyInversionReport::AddField(inverted, output->GetFieldData());
    inversionWarning =
      vtkSoftBodyInversionReport::Warning(inverted, tetCount, simulation.time(), p);
  }

  vtkSoftBodyStressOutput::Add(simulation.stressField(), simulation.restPositions(), output);
  vtkSoftBodyConditionOutput::Add(simulation.conditionReadout(), output);

  vtkFieldData* field = output->GetFieldData();
  field->AddArray(MakeScalarArray("SimulationTime", { simulation.time() }));
  if (const double elastic = simulation.elasticEnergy(); std::isfinite(elastic))
  {
    field->AddArray(MakeScalarArray("ElasticEnergy", { elastic }));
  }
  field->AddArray(MakeScalarArray("KineticEnergy", { simulation.kineticEnergy() }));
  auto steps = vtkSmartPointer<vtkIdTypeArray>::New();
  steps->SetName("StepCount");
  steps->InsertNextValue(static_cast<vtkIdType>(simulation.stepCount()));
  field->AddArray(steps);
  field->AddArray(MakeScalarArray("TimeStep", { StepUsed(simulation, p.FrameInterval) }));
  field->AddArray(MakeScalarArray("StableTimeStep", { simulation.estimatedStableStep() }));
  field->AddArray(MakeScalarArray("TotalMass", { simulation.totalMass() }));

  field->AddArray(MakeStringArray(
    "Integrator", { softbody::integratorName(vtkSoftBodySettings::Integrator(p.Integrator)) }));
  if (const softbody::PbdSimulation* pbd = built.Pbd)
  {
    built.PbdAdapter.AddBrokenCells(*pbd, output);
    vtkSoftBodyPbdAdapter::AddConvergenceFields(*pbd, output);
  }
  const softbody::ImplicitConvergence* implicit = ImplicitSolveReport(built);
  if (implicit)
  {
    vtkSoftBodyImplicitReport::AddFields(*implicit, field);
  }
  if (const softbody::StepControlReport* controller = simulation.stepControlReport())
  {
    AddStepControlFields(*controller, field);
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
  if (!built.DeviceWarning.empty())
  {
    warnings.push_back(built.DeviceWarning);
  }
  warnings.insert(warnings.end(), built.InputWarnings.begin(), built.InputWarnings.end());
  for (const std::string& said : beforeRun)
  {
    if (!said.empty())
    {
      warnings.push_back(said);
    }
  }
  if (implicit)
  {
    const std::string unconverged = vtkSoftBodyImplicitReport::Warning(*implicit,
      softbody::integratorName(vtkSoftBodySettings::Integrator(p.Integrator)),
      p.ImplicitMaxIterations);
    if (!unconverged.empty())
    {
      warnings.push_back(unconverged);
    }
    const std::string fastContact = vtkSoftBodyImplicitReport::ContactWarning(
      *implicit, softbody::integratorName(vtkSoftBodySettings::Integrator(p.Integrator)));
    if (!fastContact.empty())
    {
      warnings.push_back(fastContact);
    }
  }
  for (const std::string& warning : vtkSoftBodySettings::Warnings(p))
  {
    warnings.push_back(warning);
  }
  if (!inversionWarning.empty())
  {
    warnings.push_back(inversionWarning);
  }
  if (!surfaceWarning.empty())
  {
    warnings.push_back(surfaceWarning);
  }
  field->AddArray(MakeStringArray("Warnings", warnings));
  field->AddArray(MakeStringArray("Device", { kDeviceNames[built.DeviceUsed] }));
  field->AddArray(MakeStringArray("GLRenderer", { built.GLRenderer }));
  return inversionWarning;
}

//------------------------------------------------------------------------------
void vtkSoftBodyOutputAssembly::FillParticles(
  const vtkSoftBodyBuiltSimulation& built, vtkUnstructuredGrid* mesh, vtkPolyData* output)
{
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
  output->GetPointData()->AddArray(
    MakeScalarArray("InverseMass", built.Simulation->inverseMasses()));
}

//------------------------------------------------------------------------------
void vtkSoftBodyOutputAssembly::FillConvergence(
  const vtkSoftBodyBuiltSimulation& built, vtkTable* output)
{
  if (const softbody::PbdSimulation* pbd = built.Pbd)
  {
    vtkSoftBodyPbdAdapter::FillConvergenceTable(*pbd, output);
  }
  else if (const softbody::ImplicitConvergence* implicit = ImplicitSolveReport(built))
  {
    vtkSoftBodyImplicitReport::FillTable(*implicit, output);
  }
}

//------------------------------------------------------------------------------
void vtkSoftBodyOutputAssembly::FillSurface(const vtkSoftBodySkin& skin, vtkPolyData* surface,
  const vtkSoftBodyBuiltSimulation& built, const softbody::Scene& scene,
  const std::vector<softbody::ObstacleSurface>& obstacles, vtkPolyData* output)
{
  skin.Fill(surface, built.Simulation->positions(), output,
    scene.floorActive() ? &scene.floor : nullptr, obstacles);
}

//------------------------------------------------------------------------------
void vtkSoftBodyOutputAssembly::FillFloor(const vtkSoftBodyParameters& p,
  const softbody::Scene& scene, vtkUnstructuredGrid* input, const Outputs& outputs)
{
  double origin[3] = { p.FloorOrigin[0], p.FloorOrigin[1], p.FloorOrigin[2] };
  if (scene.floorActive())
  {
    for (int k = 0; k < 3; ++k)
    {
      origin[k] = scene.floor.origin[k];
    }
    vtkNew<vtkDoubleArray> where;
    where->SetName("FloorOrigin");
    where->SetNumberOfComponents(3);
    where->InsertNextTuple(origin);
    outputs.Mesh->GetFieldData()->AddArray(where);
  }
  vtkSoftBodyFloorOutput::Fill(p.Floor != 0, origin, p.FloorNormal, input->GetBounds(), outputs.Floor);
}
