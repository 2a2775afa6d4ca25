// filter.bad_inputs: unusable inputs and parameters end in a clear error (never a crash or an
// exception crossing the pipeline), and the same filter works again once the problem is fixed.
#include "filter_test_support.h"

#include "vtkCellArray.h"
#include "vtkSoftBodyCloth.h"
#include "vtkSoftBodyVoxelize.h"
#include "vtkSphereSource.h"
#include "vtkTetrahedralizeSurface.h"

namespace
{
/// Runs `f` at time t and checks it fails with every fragment in its error messages.
void ExpectError(sbtest::CapturedFilter& f, const char* what, std::vector<std::string> fragments,
  double t = 0.1)
{
  f.Messages->Clear();
  const bool ok = f.Update(t);
  SB_CHECK(!ok, what << ": the update should fail");
  SB_CHECK(!f.Messages->Errors.empty(), what << ": an error message is expected");
  for (const std::string& fragment : fragments)
  {
    SB_CHECK(f.Messages->ErrorContains(fragment),
      what << ": error should mention '" << fragment << "'; got:\n" << f.Messages->AllErrors());
  }
}

void ExpectSuccess(sbtest::CapturedFilter& f, const char* what)
{
  f.Messages->Clear();
  SB_CHECK(f.Update(0.1), what << ": " << f.Messages->AllErrors());
  SB_CHECK(f.Mesh()->GetNumberOfPoints() > 0, what << ": output expected");
}

vtkSmartPointer<vtkUnstructuredGrid> Box()
{
  return sbtest::MakeTetBox(2, 2, 2, 0.1, { 0.0, 0.0, 0.5 });
}

/// Appends a tet over four new points to `grid`.
void AddTet(vtkUnstructuredGrid* grid, const double p[4][3])
{
  vtkIdType ids[4];
  for (int i = 0; i < 4; ++i)
  {
    ids[i] = grid->GetPoints()->InsertNextPoint(p[i]);
  }
  grid->InsertNextCell(VTK_TETRA, 4, ids);
}
} // namespace

int main()
{
  // Empty grid: no points, no cells.
  {
    vtkNew<vtkUnstructuredGrid> empty;
    sbtest::CapturedFilter f(empty);
    ExpectError(f, "empty grid", { "empty input" });

    // ...except as one piece of a parallel run, where an empty piece is normal.
    f.Messages->Clear();
    SB_CHECK(f.Filter->UpdateTimeStep(0.1, 1, 2) == 1, "empty piece 1 of 2: " << f.Messages->AllErrors());
    SB_CHECK(f.Messages->Errors.empty(), "an empty piece is not an error");
    SB_CHECK(f.Mesh()->GetNumberOfPoints() == 0, "an empty piece gives an empty output");
  }
  // Points but no cells.
  {
    vtkNew<vtkUnstructuredGrid> noCells;
    vtkNew<vtkPoints> points;
    points->InsertNextPoint(0, 0, 0);
    noCells->SetPoints(points);
    sbtest::CapturedFilter f(noCells);
    ExpectError(f, "no cells", { "empty input" });
  }
  // Tets mixed with one hexahedron and two triangles.
  {
    auto mixed = Box();
    const vtkIdType hex[8] = { 0, 1, 4, 3, 9, 10, 13, 12 };
    mixed->InsertNextCell(VTK_HEXAHEDRON, 8, hex);
    const vtkIdType tri[3] = { 0, 1, 4 };
    mixed->InsertNextCell(VTK_TRIANGLE, 3, tri);
    mixed->InsertNextCell(VTK_TRIANGLE, 3, tri);
    sbtest::CapturedFilter f(mixed);
    ExpectError(f, "mixed cells", { "3 of the 51", "Tetrahedralize", "vtkHexahedron" });
  }
  // A NaN coordinate.
  {
    auto nan = Box();
    nan->GetPoints()->SetPoint(5, 0.1, std::nan(""), 0.6);
    sbtest::CapturedFilter f(nan);
    ExpectError(f, "NaN point", { "NaN" });
  }
  // A flat tet (four coplanar points) among good ones.
  {
    auto flat = Box();
    const double p[4][3] = { { 1, 1, 1 }, { 1.1, 1, 1 }, { 1, 1.1, 1 }, { 1.1, 1.1, 1 } };
    AddTet(flat, p);
    sbtest::CapturedFilter f(flat);
    ExpectError(f, "flat tet", { "degenerate", "48" }); // names the first bad cell
  }
  // An inverted tet: refused on request, re-oriented with a warning by default.
  {
    auto inverted = Box();
    const double p[4][3] = { { 1, 1, 1 }, { 1.1, 1, 1 }, { 1, 1, 1.1 }, { 1, 1.1, 1 } };
    AddTet(inverted, p);
    sbtest::CapturedFilter f(inverted);
    f.Filter->SetInvertedTets(vtkSoftBodyFilter::REFUSE);
    ExpectError(f, "inverted tet, Refuse", { "inverted" });

    f.Filter->SetInvertedTets(vtkSoftBodyFilter::REORIENT);
    ExpectSuccess(f, "inverted tet, Re-orient");
    const std::vector<std::string> warnings = sbtest::FieldStrings(f.Mesh(), "Warnings");
    bool mentioned = false;
    for (const std::string& w : warnings)
    {
      mentioned = mentioned || w.find("re-oriented") != std::string::npos;
    }
    SB_CHECK(mentioned, "Warnings field data should report the re-oriented tet");
    SB_CHECK(!f.Messages->Warnings.empty(), "and the filter should warn once");
  }
  // Parameters and pins on a good box; each error is then fixed and the filter recovers.
  {
    auto box = Box();
    sbtest::CapturedFilter f(box);

    f.Filter->SetPinnedPointsArray("NoSuchArray");
    ExpectError(f, "missing pin array", { "NoSuchArray" });
    f.Filter->SetPinnedPointsArray("");
    ExpectSuccess(f, "pins cleared");

    f.Filter->SetFrameInterval(0.0);
    ExpectError(f, "FrameInterval = 0", { "FrameInterval" });
    f.Filter->SetFrameInterval(0.04);

    f.Filter->SetEndTime(0.0);
    ExpectError(f, "EndTime = 0", { "EndTime" });
    f.Filter->SetEndTime(3.0);

    f.Filter->SetStrainLimit(0.5);
    ExpectError(f, "StrainLimit = 0.5", { "StrainLimit" });
    f.Filter->SetStrainLimit(1.0);
    ExpectError(f, "StrainLimit = 1", { "StrainLimit" });
    f.Filter->SetStrainLimit(0.0);

    f.Filter->SetPoissonRatio(0.5);
    ExpectError(f, "PoissonRatio = 0.5", { "PoissonRatio" });
    f.Filter->SetPoissonRatio(0.3);

    f.Filter->SetFloorNormal(0.0, 0.0, 0.0);
    ExpectError(f, "zero floor normal", { "FloorNormal" });
    f.Filter->SetFloorNormal(0.0, 0.0, 1.0);

    f.Filter->SetYoungsModulus(0.0);
    ExpectError(f, "YoungsModulus = 0", { "YoungsModulus" });
    f.Filter->SetYoungsModulus(1e5);

    ExpectSuccess(f, "all fixed");

    // Divergence: undamped explicit Euler with a step far above the stable one blows up. The
    // broken simulation and its frames are dropped; stable settings work again.
    f.Filter->SetIntegrator(vtkSoftBodyFilter::EULER);
    f.Filter->SetDampingTime(0.0);
    f.Filter->SetTimeStep(0.01);
    ExpectError(f, "divergence", { "t = ", "TimeStep" }, 3.0);
    SB_CHECK(f.Filter->GetNumberOfCachedFrames() == 0, "no frame of a diverged run is kept");
    f.Filter->SetIntegrator(vtkSoftBodyFilter::EULER_CROMER);
    f.Filter->SetDampingTime(1e-3);
    f.Filter->SetTimeStep(0.0);
    ExpectSuccess(f, "stable again");
  }
  // Enumerations out of their lists (a C++ or pvpython caller can set any int): refused with
  // the value, then the filter works again.
  {
    auto box = Box();
    sbtest::CapturedFilter f(box);
    f.Filter->SetMethod(7);
    ExpectError(f, "Method 7", { "Method must be one of", "got 7" });
    f.Filter->SetMethod(vtkSoftBodyFilter::MASS_SPRING);
    f.Filter->SetIntegrator(-1);
    ExpectError(f, "Integrator -1", { "Integrator must be one of", "got -1" });
    f.Filter->SetIntegrator(vtkSoftBodyFilter::VERLET);
    f.Filter->SetDevice(5);
    ExpectError(f, "Device 5", { "Device", "got 5" });
    f.Filter->SetDevice(vtkSoftBodyFilter::DEVICE_CPU);
    f.Filter->SetMethod(vtkSoftBodyFilter::XPBD);
    f.Filter->SetSolver(3);
    ExpectError(f, "Solver 3", { "Solver", "got 3" });
    f.Filter->SetSolver(vtkSoftBodyFilter::JACOBI);
    ExpectSuccess(f, "valid enumerations again");
  }

  // The other filters do not clamp either: a bad value is refused with the value given.
  {
    auto refuses = [](vtkAlgorithm* algorithm, const char* what, const std::string& fragment) {
      vtkNew<sbtest::MessageCatcher> messages;
      messages->Observe(algorithm);
      messages->Observe(algorithm->GetExecutive());
      algorithm->Update();
      SB_CHECK(messages->ErrorContains(fragment),
        what << ": error should mention '" << fragment << "'; got:\n" << messages->AllErrors());
    };
    vtkNew<vtkSphereSource> sphere;
    vtkNew<vtkSoftBodyVoxelize> voxelize;
    voxelize->SetInputConnection(sphere->GetOutputPort());
    voxelize->SetResolution(0);
    refuses(voxelize, "Voxelize Resolution 0", "Resolution must be >= 1, got 0");
    voxelize->SetResolution(8);
    voxelize->SetDensity(-3.0);
    refuses(voxelize, "Voxelize Density -3", "Density must be > 0 kg/m^3, got -3");
    vtkNew<vtkTetrahedralizeSurface> tetrahedralize;
    tetrahedralize->SetInputConnection(sphere->GetOutputPort());
    tetrahedralize->SetMinDihedralAngle(80.0);
    refuses(tetrahedralize, "MinDihedralAngle 80", "MinDihedralAngle must be in [0, 70], got 80");
    vtkNew<vtkSoftBodyCloth> cloth;
    cloth->SetTotalMass(-1.0);
    refuses(cloth, "Cloth TotalMass -1", "TotalMass must be > 0 kg, got -1");

    // A voxelized body (links) under Mass-Spring, chosen by the user (Automatic, the default,
    // runs XPBD on it): the advice is the method that works, not remeshing; and XPBD then
    // simulates it.
    voxelize->SetDensity(1100.0);
    vtkNew<vtkSoftBodyFilter> body;
    body->SetInputConnection(voxelize->GetOutputPort());
    body->SetMethod(vtkSoftBodyFilter::MASS_SPRING);
    refuses(body, "links under Mass-Spring", "choose Method XPBD (or PBD)");
    vtkNew<sbtest::MessageCatcher> messages;
    messages->Observe(body);
    body->SetMethod(vtkSoftBodyFilter::XPBD);
    SB_CHECK(body->UpdateTimeStep(0.04) == 1 && messages->Errors.empty(),
      "the voxelized body runs under XPBD: " << messages->AllErrors());
  }

  return sbtest::Result("filter.bad_inputs");
}
