// filter.mesh_quality: vtkSoftBodyMeshQuality's arrays, histogram table and summary agree with
// core's report on a hand-built mesh (regular, right-corner, sliver and inverted tets), VTK's
// metrics agree with core's geometry, and bad input ends in a clear error.
#include "filter_test_support.h"

#include "vtkCellData.h"
#include "vtkSoftBodyMeshQuality.h"
#include "vtkTable.h"

#include "softbody/stability/stability_report.h"

#include <numeric>

namespace
{
/// Regular, right-corner, sliver and inverted right-corner tets, disjoint along x.
vtkSmartPointer<vtkUnstructuredGrid> MakeQualityMesh()
{
  const double corners[4][4][3] = {
    { { 1, 1, 1 }, { 1, -1, -1 }, { -1, -1, 1 }, { -1, 1, -1 } },     // regular, positive
    { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },           // right corner
    { { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0.02 }, { 0, 1, 0.02 } },   // sliver (orientation below)
    { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 0 } },           // right corner, inverted
  };
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  grid->Allocate(4);
  for (int t = 0; t < 4; ++t)
  {
    vtkIdType ids[4];
    for (int k = 0; k < 4; ++k)
    {
      ids[k] = points->InsertNextPoint(corners[t][k][0] + 5.0 * t, corners[t][k][1], corners[t][k][2]);
    }
    if (t == 2 && sbtest::TetVolume(corners[t][0], corners[t][1], corners[t][2], corners[t][3]) < 0.0)
    {
      std::swap(ids[2], ids[3]);
    }
    grid->InsertNextCell(VTK_TETRA, 4, ids);
  }
  grid->SetPoints(points);
  return grid;
}

softbody::TetMesh ToCore(vtkUnstructuredGrid* grid)
{
  softbody::TetMesh mesh;
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    double x[3];
    grid->GetPoint(p, x);
    mesh.points.emplace_back(x[0], x[1], x[2]);
  }
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    vtkIdType npts = 0;
    const vtkIdType* pts = nullptr;
    grid->GetCellPoints(c, npts, pts);
    mesh.tets.push_back({ static_cast<std::int32_t>(pts[0]), static_cast<std::int32_t>(pts[1]),
      static_cast<std::int32_t>(pts[2]), static_cast<std::int32_t>(pts[3]) });
  }
  return mesh;
}

vtkDataArray* CellArray(vtkUnstructuredGrid* grid, const char* name)
{
  return grid ? grid->GetCellData()->GetArray(name) : nullptr;
}

void CheckArraysAgainstCore()
{
  auto input = MakeQualityMesh();
  vtkNew<vtkSoftBodyMeshQuality> filter;
  filter->SetInputData(input);
  filter->SetNumberOfBins(8);
  filter->Update();
  auto* mesh = vtkUnstructuredGrid::SafeDownCast(filter->GetOutputDataObject(0));
  auto* table = vtkTable::SafeDownCast(filter->GetOutputDataObject(1));
  SB_CHECK(mesh && table, "both outputs exist");
  if (!mesh || !table)
  {
    return;
  }

  const softbody::MassSpringQualityReport core = softbody::computeMassSpringQuality(
    ToCore(input), softbody::MaterialSettings(), softbody::Integrator::EulerCromer);

  vtkDataArray* volume = CellArray(mesh, "Volume");
  vtkDataArray* angle = CellArray(mesh, "MinDihedralAngle");
  vtkDataArray* aspect = CellArray(mesh, "AspectRatio");
  vtkDataArray* inverted = CellArray(mesh, "Inverted");
  vtkDataArray* degenerate = CellArray(mesh, "Degenerate");
  vtkDataArray* sliver = CellArray(mesh, "Sliver");
  vtkDataArray* inverseMass = mesh->GetPointData()->GetArray("InverseMass");
  SB_CHECK(volume && angle && aspect && inverted && degenerate && sliver && inverseMass,
    "all quality arrays are present");
  if (!(volume && angle && aspect && inverted && degenerate && sliver && inverseMass))
  {
    return;
  }
  for (vtkIdType c = 0; c < 4; ++c)
  {
    const auto t = static_cast<std::size_t>(c);
    // VTK's (verdict's) volume has core's sign convention.
    SB_CHECK(std::abs(volume->GetTuple1(c) - core.signedVolume[t]) <= 1e-12 * std::abs(core.signedVolume[t]),
      "cell " << c << ": VTK volume " << volume->GetTuple1(c) << " vs core " << core.signedVolume[t]);
    SB_CHECK(angle->GetTuple1(c) == core.minDihedralDegrees[t],
      "cell " << c << ": min angle " << angle->GetTuple1(c) << " vs core " << core.minDihedralDegrees[t]);
    SB_CHECK(inverted->GetTuple1(c) == (volume->GetTuple1(c) < 0.0 ? 1.0 : 0.0), "Inverted matches Volume's sign");
    SB_CHECK(sliver->GetTuple1(c) == (angle->GetTuple1(c) < filter->GetSliverAngle() ? 1.0 : 0.0),
      "Sliver matches MinDihedralAngle < SliverAngle");
    SB_CHECK(degenerate->GetTuple1(c) == 0.0, "no tet here is degenerate");
    SB_CHECK(aspect->GetTuple1(c) >= 1.0 - 1e-12, "aspect ratios are at least 1 (regular tet)");
  }
  SB_CHECK(std::abs(angle->GetTuple1(0) - 70.528779365509308) < 1e-6, "regular tet: 70.53 degrees");
  SB_CHECK(std::abs(aspect->GetTuple1(0) - 1.0) < 1e-9, "regular tet: aspect ratio 1");
  SB_CHECK(sliver->GetTuple1(2) == 1.0 && inverted->GetTuple1(3) == 1.0, "the sliver and the inverted tet are flagged");
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    SB_CHECK(inverseMass->GetTuple1(p) == core.inverseMass[static_cast<std::size_t>(p)] && inverseMass->GetTuple1(p) > 0.0,
      "point " << p << ": InverseMass equals core's");
  }

  // Histograms: 8 rows, counts summing to points (16), tets (4) and distinct edges (24).
  SB_CHECK(table->GetNumberOfRows() == 8 && table->GetNumberOfColumns() == 6, "histogram table shape");
  auto columnSum = [&](const char* name) {
    vtkDataArray* column = vtkDataArray::SafeDownCast(table->GetColumnByName(name));
    double total = 0.0;
    for (vtkIdType r = 0; column && r < column->GetNumberOfTuples(); ++r)
    {
      total += column->GetTuple1(r);
    }
    return column ? total : -1.0;
  };
  SB_CHECK(columnSum("InverseMassCount") == 16.0, "inverse-mass counts sum to the points");
  SB_CHECK(columnSum("VolumeCount") == 4.0, "volume counts sum to the tets");
  SB_CHECK(columnSum("EdgeLengthCount") == 24.0, "edge-length counts sum to the edges");
  SB_CHECK(table->GetColumnByName("InverseMass") && table->GetColumnByName("Volume") &&
      table->GetColumnByName("EdgeLength"),
    "bin-center columns are present");

  // The summary, on both outputs.
  for (vtkDataObject* data : { static_cast<vtkDataObject*>(mesh), static_cast<vtkDataObject*>(table) })
  {
    SB_CHECK(sbtest::FieldValue(data, "SliverTets") == 1.0, "SliverTets");
    SB_CHECK(sbtest::FieldValue(data, "InvertedTets") == 1.0, "InvertedTets");
    SB_CHECK(sbtest::FieldValue(data, "DegenerateTets") == 0.0, "DegenerateTets");
    SB_CHECK(sbtest::FieldValue(data, "StableTimeStep") == core.stableTimeStep && core.stableTimeStep > 0.0,
      "StableTimeStep equals core's");
    SB_CHECK(sbtest::FieldValue(data, "TruncatedStableTimeStep") == core.truncatedStableTimeStep,
      "TruncatedStableTimeStep equals core's");
    SB_CHECK(sbtest::FieldValue(data, "SuggestedMaxInverseMass") == core.suggestedMaxInverseMass,
      "SuggestedMaxInverseMass equals core's");
    SB_CHECK(std::abs(sbtest::FieldValue(data, "MinDihedralAngle") - angle->GetTuple1(2)) < 1e-6,
      "MinDihedralAngle is the sliver's");
    SB_CHECK(sbtest::FieldStrings(data, "Integrator").size() == 1, "Integrator named");
  }
}

void CheckBadInputs()
{
  // Not tetrahedra: the Soft Body filter's own message.
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  points->InsertNextPoint(1, 0, 0);
  points->InsertNextPoint(0, 1, 0);
  grid->SetPoints(points);
  const vtkIdType tri[3] = { 0, 1, 2 };
  grid->InsertNextCell(VTK_TRIANGLE, 3, tri);

  vtkNew<vtkSoftBodyMeshQuality> filter;
  vtkNew<sbtest::MessageCatcher> messages;
  messages->Observe(filter);
  messages->Observe(filter->GetExecutive());
  filter->SetInputData(grid);
  SB_CHECK(filter->GetExecutive()->Update() == 0, "non-tet input fails");
  SB_CHECK(messages->ErrorContains("not tetrahedra"), "says the cells are not tets: " << messages->AllErrors());

  // Bad material: core's message, then recovery on the same filter.
  messages->Clear();
  filter->SetInputData(sbtest::MakeTetBox(2, 2, 2, 0.1, { 0, 0, 0 }));
  filter->SetYoungsModulus(0.0);
  SB_CHECK(filter->GetExecutive()->Update() == 0, "zero Young's modulus fails");
  SB_CHECK(messages->ErrorContains("YoungsModulus"), "names YoungsModulus: " << messages->AllErrors());
  messages->Clear();
  filter->SetYoungsModulus(2e5);
  SB_CHECK(filter->GetExecutive()->Update() == 1 && messages->Errors.empty(), "works again once fixed");
  SB_CHECK(sbtest::FieldValue(filter->GetOutputDataObject(0), "SliverTets") == 0.0, "a Kuhn box has no slivers");

  // A tet naming a missing point: counted and left unmeasured (NaN), never dereferenced.
  auto broken = sbtest::MakeTetBox(1, 1, 1, 0.1, { 0, 0, 0 });
  const vtkIdType missing[4] = { 0, 1, 2, 99 };
  broken->InsertNextCell(VTK_TETRA, 4, missing);
  messages->Clear();
  filter->SetInputData(broken);
  SB_CHECK(filter->GetExecutive()->Update() == 1, "a bad point id is reported, not fatal: " << messages->AllErrors());
  auto* out = vtkUnstructuredGrid::SafeDownCast(filter->GetOutputDataObject(0));
  SB_CHECK(sbtest::FieldValue(out, "BadIndexTets") == 1.0, "BadIndexTets counts it");
  vtkDataArray* volume = CellArray(out, "Volume");
  SB_CHECK(volume && std::isnan(volume->GetTuple1(6)) && volume->GetTuple1(5) > 0.0, "its volume is NaN, the others measured");
}
} // namespace

int main()
{
  CheckArraysAgainstCore();
  CheckBadInputs();
  return sbtest::Result("filter.mesh_quality");
}
