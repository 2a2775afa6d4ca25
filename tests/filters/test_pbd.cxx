// filter.pbd: the Soft Body filter with Method PBD and XPBD, on the Soft Body Cloth source and
// on a tet box: pinned corners hold, every solver runs, the Convergence table and the
// Iterations/Residual fields describe the last step, broken cells are flagged and hidden,
// replay comes from the cache, and inputs PBD cannot take are refused clearly.
#include "filter_test_support.h"

#include "vtkCellData.h"
#include "vtkDataSetAttributes.h"
#include "vtkHexahedron.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkSoftBodyCloth.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

namespace
{
vtkSmartPointer<vtkUnstructuredGrid> MakeCloth(int n)
{
  vtkNew<vtkSoftBodyCloth> cloth;
  cloth->SetResolution(n, n);
  cloth->Update();
  auto copy = vtkSmartPointer<vtkUnstructuredGrid>::New();
  copy->DeepCopy(cloth->GetOutput());
  return copy;
}
} // namespace

int main()
{
  // --- The cloth source itself.
  vtkSmartPointer<vtkUnstructuredGrid> cloth = MakeCloth(10);
  SB_CHECK(cloth->GetNumberOfPoints() == 100, "10 x 10 particles");
  // Structural 2 * 10 * 9, diagonals 2 * 9 * 9, quads 9 * 9.
  SB_CHECK(cloth->GetNumberOfCells() == 180 + 162 + 81, "cells: " << cloth->GetNumberOfCells());
  SB_CHECK(cloth->GetPointData()->GetArray("Pinned")->GetRange()[1] == 1.0, "pinned corners marked");

  // --- Each solver, PBD and XPBD: pinned corners hold, the rest falls, convergence reported.
  const std::vector<double> rest = sbtest::PointsOf(cloth);
  for (int method : { vtkSoftBodyFilter::PBD, vtkSoftBodyFilter::XPBD })
  {
    for (int solver : { vtkSoftBodyFilter::GAUSS_SEIDEL, vtkSoftBodyFilter::JACOBI,
           vtkSoftBodyFilter::PARALLEL_GAUSS_SEIDEL })
    {
      sbtest::CapturedFilter f(cloth);
      f.Filter->SetMethod(method);
      f.Filter->SetSolver(solver);
      f.Filter->SetPinnedPointsArray("Pinned");
      f.Filter->SetFloor(0);
      f.Filter->SetEndTime(0.5);
      f.Filter->SetFrameInterval(0.1);
      f.Filter->SetIterations(12);
      SB_CHECK(f.Update(0.5), f.Messages->AllErrors());
      const std::vector<double> now = sbtest::PointsOf(f.Mesh());
      SB_CHECK(std::memcmp(&now[3 * 90], &rest[3 * 90], 3 * sizeof(double)) == 0, "pinned corner 90 moved");
      SB_CHECK(std::memcmp(&now[3 * 99], &rest[3 * 99], 3 * sizeof(double)) == 0, "pinned corner 99 moved");
      SB_CHECK(now[2] < rest[2] - 0.2, "the free edge falls (z " << now[2] << ")");
      SB_CHECK(sbtest::FieldValue(f.Mesh(), "Iterations") == 12, "Iterations field");
      SB_CHECK(sbtest::FieldValue(f.Mesh(), "Residual") >= 0, "Residual field");
      vtkTable* table = vtkTable::SafeDownCast(f.Filter->GetOutputDataObject(vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Convergence)));
      SB_CHECK(table && table->GetNumberOfRows() == 12, "one convergence row per iteration");
      if (table && table->GetNumberOfRows() == 12)
      {
        SB_CHECK(table->GetColumnByName("Residual")->GetVariantValue(11).ToDouble() ==
            sbtest::FieldValue(f.Mesh(), "Residual"),
          "the last row is the frame's residual");
      }
      SB_CHECK(f.Messages->Errors.empty(), f.Messages->AllErrors());
    }
  }

  // --- Cache: replaying a frame costs no step and gives the same points.
  {
    sbtest::CapturedFilter f(cloth);
    f.Filter->SetMethod(vtkSoftBodyFilter::XPBD);
    f.Filter->SetPinnedPointsArray("Pinned");
    f.Filter->SetEndTime(0.4);
    f.Filter->SetFrameInterval(0.1);
    SB_CHECK(f.Update(0.3), f.Messages->AllErrors());
    const std::vector<double> first = sbtest::PointsOf(f.Mesh());
    SB_CHECK(f.Update(0.1), f.Messages->AllErrors());
    const unsigned long long steps = f.Filter->GetSimulatedStepsTotal();
    SB_CHECK(f.Update(0.3), f.Messages->AllErrors());
    SB_CHECK(f.Filter->GetSimulatedStepsTotal() == steps, "replay should come from the cache");
    SB_CHECK(sbtest::PointsOf(f.Mesh()) == first, "replayed frame differs");
    f.Filter->SetIterations(3);
    SB_CHECK(f.Update(0.3), f.Messages->AllErrors());
    SB_CHECK(f.Filter->GetSimulatedStepsTotal() > steps, "a parameter change re-simulates");
  }

  // --- Breaking: a dense column hanging from its top face tears; broken cells are hidden.
  // The parallel solver stores its constraints color by color: its outputs must still map onto
  // the input cells (VolumeRatio checked against the output points).
  for (int solver : { vtkSoftBodyFilter::GAUSS_SEIDEL, vtkSoftBodyFilter::PARALLEL_GAUSS_SEIDEL })
  {
    auto column = sbtest::MakeTetBox(1, 1, 6, 0.05, { 0.0, 0.0, 1.0 });
    vtkNew<vtkIntArray> top;
    top->SetName("Top");
    top->SetNumberOfTuples(column->GetNumberOfPoints());
    for (vtkIdType i = 0; i < column->GetNumberOfPoints(); ++i)
    {
      top->SetValue(i, column->GetPoint(i)[2] > 1.3 - 1e-6 ? 1 : 0);
    }
    column->GetPointData()->AddArray(top);
    sbtest::CapturedFilter f(column);
    f.Filter->SetMethod(vtkSoftBodyFilter::XPBD);
    f.Filter->SetSolver(solver);
    f.Filter->SetPinnedPointsArray("Top");
    f.Filter->SetDensity(20000);
    f.Filter->SetXPBDLinkCompliance(1e-3);
    f.Filter->SetBreakingStrain(0.2);
    f.Filter->SetFloor(0);
    f.Filter->SetEndTime(1.0);
    f.Filter->SetFrameInterval(0.5);
    SB_CHECK(f.Update(1.0), f.Messages->AllErrors());
    vtkDataArray* broken = f.Mesh()->GetCellData()->GetArray("Broken");
    vtkUnsignedCharArray* ghosts = f.Mesh()->GetCellGhostArray();
    SB_CHECK(broken && broken->GetRange()[1] == 1.0, "some tets broke");
    SB_CHECK(ghosts != nullptr, "broken cells are hidden through vtkGhostType");
    for (vtkIdType c = 0; broken && ghosts && c < f.Mesh()->GetNumberOfCells(); ++c)
    {
      const bool hidden = (ghosts->GetValue(c) & vtkDataSetAttributes::HIDDENCELL) != 0;
      SB_CHECK(hidden == (broken->GetTuple1(c) != 0), "cell " << c << " hidden iff broken");
    }
    SB_CHECK(column->GetCellGhostArray() == nullptr, "the input is not modified");
    vtkDataArray* ratio = f.Mesh()->GetCellData()->GetArray("VolumeRatio");
    SB_CHECK(ratio != nullptr, "VolumeRatio present");
    // InvertedTets counts the inverted tets that still hold their volume, not broken ones.
    vtkIdType invertedWhole = 0;
    for (vtkIdType c = 0; ratio && broken && c < f.Mesh()->GetNumberOfCells(); ++c)
    {
      invertedWhole += ratio->GetTuple1(c) <= 0.0 && broken->GetTuple1(c) == 0.0 ? 1 : 0;
    }
    vtkDataArray* reported = f.Mesh()->GetFieldData()->GetArray("InvertedTets");
    SB_CHECK(reported && reported->GetTuple1(0) == static_cast<double>(invertedWhole),
      "InvertedTets " << (reported ? reported->GetTuple1(0) : -1.0) << " counts the unbroken inverted tets ("
                      << invertedWhole << ")");
    for (vtkIdType c = 0; ratio && c < f.Mesh()->GetNumberOfCells(); ++c)
    {
      const vtkIdType* ids = nullptr;
      vtkIdType npts = 0;
      f.Mesh()->GetCellPoints(c, npts, ids);
      double now[4][3], atRest[4][3];
      for (int k = 0; k < 4; ++k)
      {
        f.Mesh()->GetPoint(ids[k], now[k]);
        column->GetPoint(ids[k], atRest[k]);
      }
      const double expected = sbtest::TetVolume(now[0], now[1], now[2], now[3]) /
        sbtest::TetVolume(atRest[0], atRest[1], atRest[2], atRest[3]);
      SB_CHECK(std::abs(ratio->GetTuple1(c) - expected) < 1e-9, "VolumeRatio of cell " << c);
    }
  }

  // --- Tets and line cells in one input: the line is a link, VolumeRatio maps onto the tets.
  {
    auto mixed = sbtest::MakeTetBox(2, 2, 2, 0.1, { 0.0, 0.0, 0.0 });
    const vtkIdType tets = mixed->GetNumberOfCells();
    const vtkIdType line[2] = { 0, mixed->GetNumberOfPoints() - 1 }; // a long diagonal brace
    mixed->InsertNextCell(VTK_LINE, 2, line);
    sbtest::CapturedFilter f(mixed);
    f.Filter->SetMethod(vtkSoftBodyFilter::XPBD);
    f.Filter->SetEndTime(0.2);
    f.Filter->SetFrameInterval(0.1);
    SB_CHECK(f.Update(0.2), f.Messages->AllErrors());
    vtkDataArray* ratio = f.Mesh()->GetCellData()->GetArray("VolumeRatio");
    SB_CHECK(ratio && ratio->GetNumberOfTuples() == tets + 1, "VolumeRatio per input cell");
    if (ratio && ratio->GetNumberOfTuples() == tets + 1)
    {
      SB_CHECK(std::isnan(ratio->GetTuple1(tets)), "the line cell has no volume ratio");
      SB_CHECK(std::abs(ratio->GetTuple1(0) - 1.0) < 0.05, "tet 0 keeps its volume");
    }
    double a[3], b[3];
    f.Mesh()->GetPoint(line[0], a);
    f.Mesh()->GetPoint(line[1], b);
    const double length = std::sqrt(vtkMath::Distance2BetweenPoints(a, b));
    SB_CHECK(std::abs(length - std::sqrt(3 * 0.04)) < 1e-3, "the brace keeps its length (" << length << ")");
  }

  // --- XPBD from Young's modulus: a bar hanging from its top sags about 4x more at E / 4.
  {
    auto bar = sbtest::MakeTetBox(2, 2, 8, 0.025, { 0.0, 0.0, 1.0 });
    vtkNew<vtkIntArray> top;
    top->SetName("Top");
    top->SetNumberOfTuples(bar->GetNumberOfPoints());
    for (vtkIdType i = 0; i < bar->GetNumberOfPoints(); ++i)
    {
      top->SetValue(i, bar->GetPoint(i)[2] > 1.2 - 1e-6 ? 1 : 0);
    }
    bar->GetPointData()->AddArray(top);
    double sag[2] = { 0.0, 0.0 };
    for (int k = 0; k < 2; ++k)
    {
      sbtest::CapturedFilter f(bar);
      f.Filter->SetMethod(vtkSoftBodyFilter::XPBD);
      f.Filter->SetXPBDMaterial(vtkSoftBodyFilter::XPBD_YOUNGS_MODULUS);
      f.Filter->SetYoungsModulus(k == 0 ? 2.0e5 : 5.0e4);
      f.Filter->SetPinnedPointsArray("Top");
      f.Filter->SetIterations(20);
      f.Filter->SetSubsteps(4);
      f.Filter->SetVelocityDamping(10.0);
      f.Filter->SetFloor(0);
      f.Filter->SetEndTime(2.0);
      f.Filter->SetFrameInterval(1.0);
      SB_CHECK(f.Update(2.0), f.Messages->AllErrors());
      sag[k] = 1.0 - f.Mesh()->GetPoint(0)[2];
    }
    SB_CHECK(sag[0] > 1e-4 && std::abs(sag[1] / sag[0] - 4.0) < 0.4,
      "sag " << sag[0] << " m at 2e5 Pa, " << sag[1] << " m at 5e4 Pa (ratio " << sag[1] / sag[0] << ")");
  }

  // --- Inputs PBD refuses, with a message that says why.
  {
    sbtest::CapturedFilter f(cloth);
    f.Filter->SetMethod(vtkSoftBodyFilter::PBD);
    f.Filter->SetIntegrator(vtkSoftBodyFilter::MIDPOINT);
    SB_CHECK(!f.Update(0.04), "Midpoint is not a PBD predictor");
    SB_CHECK(f.Messages->AllErrors().find("Euler-Cromer") != std::string::npos, f.Messages->AllErrors());
  }
  {
    vtkNew<vtkUnstructuredGrid> hex;
    vtkNew<vtkPoints> points;
    for (int k = 0; k < 8; ++k)
    {
      points->InsertNextPoint(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    }
    hex->SetPoints(points);
    const vtkIdType ids[8] = { 0, 1, 3, 2, 4, 5, 7, 6 };
    hex->InsertNextCell(VTK_HEXAHEDRON, 8, ids);
    sbtest::CapturedFilter f(hex);
    f.Filter->SetMethod(vtkSoftBodyFilter::XPBD);
    SB_CHECK(!f.Update(0.04), "hexahedra are refused");
    SB_CHECK(f.Messages->AllErrors().find("Tetrahedralize") != std::string::npos, f.Messages->AllErrors());
  }
  {
    // Links without a Mass array and without tets: nothing to weigh them by.
    auto noMass = MakeCloth(4);
    noMass->GetPointData()->RemoveArray("Mass");
    sbtest::CapturedFilter f(noMass);
    f.Filter->SetMethod(vtkSoftBodyFilter::XPBD);
    SB_CHECK(!f.Update(0.04), "a cloth without masses is refused");
    SB_CHECK(f.Messages->AllErrors().find("Mass") != std::string::npos, f.Messages->AllErrors());
  }
  return sbtest::Result("filter.pbd");
}
