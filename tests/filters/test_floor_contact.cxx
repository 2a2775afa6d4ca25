// filter.floor_contact: a box dropped onto the floor stays above it and comes to rest there,
// without the floor it falls through (so the check can fail); the input is never modified; the
// outputs carry the documented arrays with the documented shapes.
#include "filter_test_support.h"

#include "vtkCellData.h"
#include "vtkCubeSource.h"
#include "vtkPolyData.h"

#include <sstream>

namespace
{
double MinZ(const std::vector<double>& xyz)
{
  double minZ = 1e300;
  for (std::size_t i = 2; i < xyz.size(); i += 3)
  {
    minZ = std::min(minZ, xyz[i]);
  }
  return minZ;
}
} // namespace

int main()
{
  // 0.15 m box, bottom 0.1 m above the floor: it lands after ~0.14 s.
  auto box = sbtest::MakeTetBox(3, 3, 3, 0.05, { 0.0, 0.0, 0.1 });
  vtkNew<vtkDoubleArray> tag; // an input array that must pass through untouched
  tag->SetName("Tag");
  tag->SetNumberOfTuples(box->GetNumberOfPoints());
  for (vtkIdType i = 0; i < box->GetNumberOfPoints(); ++i)
  {
    tag->SetValue(i, double(i));
  }
  box->GetPointData()->AddArray(tag);
  const std::vector<double> inputBefore = sbtest::PointsOf(box);
  const vtkMTimeType inputMTime = box->GetMTime();

  sbtest::CapturedFilter f(box);
  f.Filter->SetEndTime(1.0);
  f.Filter->SetFrameInterval(0.05);
  const double tolerance = 1e-9; // the floor projects points exactly onto the plane
  // Resting on it means within the contact margin: automatic, a tenth of the mean surface
  // edge (between 0.005 m and 0.0071 m here).
  const double kResting = 0.1 * 0.05 * std::sqrt(2.0) + 1e-3;
  double lastMinZ = 0.0;
  for (double t : { 0.1, 0.2, 0.3, 0.5, 1.0 })
  {
    SB_CHECK(f.Update(t), f.Messages->AllErrors());
    lastMinZ = MinZ(sbtest::PointsOf(f.Mesh()));
    SB_CHECK(lastMinZ >= -tolerance, "at t = " << t << " a point is below the floor: z = " << lastMinZ);
  }
  SB_CHECK(lastMinZ < kResting,
    "the box has reached the floor by t = 1 s (min z = " << lastMinZ << ")");

  // At rest on the floor: small velocities, bounded deformation.
  vtkUnstructuredGrid* mesh = f.Mesh();
  vtkDataArray* velocity = mesh->GetPointData()->GetArray("Velocity");
  SB_CHECK(velocity && velocity->GetNumberOfComponents() == 3 &&
      velocity->GetNumberOfTuples() == box->GetNumberOfPoints(),
    "Velocity: 3 components per point");
  double maxSpeed = 0.0;
  for (vtkIdType i = 0; velocity && i < velocity->GetNumberOfTuples(); ++i)
  {
    const double* v = velocity->GetTuple3(i);
    maxSpeed = std::max(maxSpeed, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  }
  SB_CHECK(maxSpeed < 0.2, "the box should be settling at t = 1 s (max speed " << maxSpeed << " m/s)");

  // Documented output shape.
  SB_CHECK(mesh->GetNumberOfPoints() == box->GetNumberOfPoints(), "same point count");
  SB_CHECK(mesh->GetNumberOfCells() == box->GetNumberOfCells(), "same cell count");
  SB_CHECK(mesh->GetPointData()->GetArray("Displacement") &&
      mesh->GetPointData()->GetArray("Displacement")->GetNumberOfComponents() == 3,
    "Displacement array");
  vtkDataArray* passed = mesh->GetPointData()->GetArray("Tag");
  SB_CHECK(passed && passed->GetTuple1(7) == 7.0, "input point arrays pass through");
  vtkDataArray* ratio = mesh->GetCellData()->GetArray("VolumeRatio");
  SB_CHECK(ratio && ratio->GetNumberOfTuples() == box->GetNumberOfCells(), "VolumeRatio per cell");
  if (ratio)
  {
    double range[2];
    ratio->GetRange(range);
    SB_CHECK(range[0] > 0.5 && range[1] < 1.5, "volume ratios near 1: " << range[0] << ".." << range[1]);
  }
  for (const char* name : { "SimulationTime", "StepCount", "TimeStep", "StableTimeStep", "TotalMass" })
  {
    SB_CHECK(!std::isnan(sbtest::FieldValue(mesh, name)), "field data " << name);
  }
  // Default material: 0.15^3 m^3 of 1100 kg/m^3.
  SB_CHECK(std::abs(sbtest::FieldValue(mesh, "TotalMass") - 1100.0 * 0.15 * 0.15 * 0.15) < 1e-3,
    "TotalMass " << sbtest::FieldValue(mesh, "TotalMass"));
  SB_CHECK(sbtest::FieldValue(mesh, "TimeStep") > 0.0, "automatic time step chosen");
  SB_CHECK(sbtest::FieldStrings(mesh, "Integrator").size() == 1, "Integrator name");
  const std::vector<std::string> plan = sbtest::FieldStrings(mesh, "Plan");
  vtkDataArray* stageSeconds = mesh->GetFieldData()->GetArray("StageSeconds");
  SB_CHECK(!plan.empty() && stageSeconds &&
      stageSeconds->GetNumberOfTuples() == static_cast<vtkIdType>(plan.size()),
    "StageSeconds parallel to Plan");
  SB_CHECK(stageSeconds && stageSeconds->GetTuple1(0) > 0.0,
    "the first stage (forces) has been timed: " << (stageSeconds ? stageSeconds->GetTuple1(0) : -1.0));
  SB_CHECK(mesh->GetFieldData()->GetAbstractArray("Warnings") != nullptr, "Warnings array present");

  vtkPolyData* particles = vtkPolyData::SafeDownCast(f.Filter->GetOutputDataObject(vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Particles)));
  SB_CHECK(particles && particles->GetNumberOfPoints() == box->GetNumberOfPoints() &&
      particles->GetNumberOfVerts() == box->GetNumberOfPoints(),
    "particles: the points, one vertex each");
  SB_CHECK(particles && particles->GetPointData()->GetArray("Velocity") &&
      particles->GetPointData()->GetArray("InverseMass"),
    "particle arrays");
  SB_CHECK(particles && sbtest::BitwiseEqual(sbtest::PointsOf(particles), sbtest::PointsOf(mesh)),
    "particles sit on the mesh points");

  // The input is read, never written.
  SB_CHECK(sbtest::BitwiseEqual(sbtest::PointsOf(box), inputBefore), "input points unchanged");
  SB_CHECK(box->GetMTime() == inputMTime, "input not modified");
  SB_CHECK(box->GetPointData()->GetArray("Velocity") == nullptr, "no arrays added to the input");

  // Without the floor the same box falls through it: the floor check above can fail.
  f.Filter->FloorOff();
  SB_CHECK(f.Update(1.0), f.Messages->AllErrors());
  SB_CHECK(MinZ(sbtest::PointsOf(f.Mesh())) < -1.0, "without floor the box falls below z = -1");

  // A tilted floor: nothing crosses the plane through the origin with normal (0.1, 0, 1).
  f.Filter->FloorOn();
  f.Filter->SetFloorNormal(0.1, 0.0, 1.0);
  SB_CHECK(f.Update(1.0), f.Messages->AllErrors());
  const std::vector<double> tilted = sbtest::PointsOf(f.Mesh());
  double lowest = 1e300;
  for (std::size_t i = 0; i < tilted.size(); i += 3)
  {
    lowest = std::min(lowest, (0.1 * tilted[i] + tilted[i + 2]) / std::sqrt(1.01));
  }
  SB_CHECK(lowest >= -tolerance && lowest < kResting,
    "tilted floor: lowest point at " << lowest << " m from the plane (resting on it expected)");

  // PrintSelf covers every property.
  std::ostringstream printed;
  f.Filter->Print(printed);
  for (const char* name : { "YoungsModulus", "FloorNormal: 0.1 0 1", "CacheMemoryLimit: 512 MiB",
         "PinnedPointsArray", "StrainLimitIterations: 4", "InvertedTets: 0" })
  {
    SB_CHECK(printed.str().find(name) != std::string::npos, "PrintSelf lacks " << name);
  }

  SB_CHECK(f.Messages->Errors.empty(), f.Messages->AllErrors());

  // A Surface reaching 2 cm below the body (bound by extrapolation, as a voxelized body's is)
  // stays on the floor once the body rests there: the skin alone would put it 2 cm below.
  {
    vtkNew<vtkCubeSource> cube;
    cube->SetBounds(-0.01, 0.16, -0.01, 0.16, 0.08, 0.26);
    cube->Update();
    sbtest::CapturedFilter g(box);
    g.Filter->SetInputData(1, cube->GetOutput());
    g.Filter->SetEndTime(1.0);
    SB_CHECK(g.Update(1.0), g.Messages->AllErrors());
    vtkPolyData* skinned = vtkPolyData::SafeDownCast(g.Filter->GetOutputDataObject(vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Surface)));
    const double surfaceMinZ = skinned ? MinZ(sbtest::PointsOf(skinned)) : -1.0;
    SB_CHECK(surfaceMinZ >= -tolerance && surfaceMinZ < 1e-3,
      "the skinned surface rests on the floor: min z = " << surfaceMinZ);
    SB_CHECK(MinZ(sbtest::PointsOf(g.Mesh())) < kResting, "the body rests on the floor");
  }
  return sbtest::Result("filter.floor_contact");
}
