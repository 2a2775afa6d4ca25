// filter.meshing: one pipeline from a surface to a simulated body (vtkSphereSource ->
// vtkTetrahedralizeSurface -> vtkSoftBodyFilter), TetrahedralizeSurface's properties and
// errors, and the TetGen and Gmsh readers on files written here and on the shared meshes.
#include "filter_test_support.h"

#include "vtkCellArray.h"
#include "vtkGmshReader.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkTetGenReader.h"
#include "vtkTetrahedralizeSurface.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace
{
/// Total and smallest signed volume of the tets of a grid.
std::pair<double, double> Volumes(vtkUnstructuredGrid* grid)
{
  double total = 0.0, smallest = VTK_DOUBLE_MAX;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    const vtkIdType* ids = nullptr;
    vtkIdType n = 0;
    grid->GetCellPoints(c, n, ids);
    double p[4][3];
    for (int k = 0; k < 4; ++k)
    {
      grid->GetPoint(ids[k], p[k]);
    }
    const double v = sbtest::TetVolume(p[0], p[1], p[2], p[3]);
    total += v;
    smallest = std::min(smallest, v);
  }
  return { total, smallest };
}

bool AllTets(vtkUnstructuredGrid* grid)
{
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    if (grid->GetCellType(c) != VTK_TETRA)
    {
      return false;
    }
  }
  return grid->GetNumberOfCells() > 0;
}

void SurfaceToSimulatedBody()
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(0.1);
  sphere->SetCenter(0.0, 0.0, 0.3);
  sphere->SetThetaResolution(24);
  sphere->SetPhiResolution(16);
  vtkNew<vtkTetrahedralizeSurface> mesher;
  mesher->SetInputConnection(sphere->GetOutputPort());
  mesher->SetMaxRadiusEdgeRatio(1.5);
  mesher->SetMaxTetVolume(1e-3);
  mesher->MaxTetVolumeIsRelativeOn();
  vtkNew<sbtest::MessageCatcher> messages;
  messages->Observe(mesher);

  vtkNew<vtkSoftBodyFilter> body;
  body->SetInputConnection(mesher->GetOutputPort());
  body->SetEndTime(0.2);
  messages->Observe(body);
  SB_CHECK(body->UpdateTimeStep(0.2) == 1, "surface -> tets -> soft body: " << messages->AllErrors());

  vtkUnstructuredGrid* tets = mesher->GetOutput();
  const auto [volume, smallest] = Volumes(tets);
  std::printf("sphere source: %lld tets, volume %.6g (smallest tet %.3g)\n",
    static_cast<long long>(tets->GetNumberOfCells()), volume, smallest);
  SB_CHECK(AllTets(tets), "the mesher outputs tetrahedra only");
  SB_CHECK(smallest > 0.0, "every tet is positively oriented");
  SB_CHECK(tets->GetNumberOfCells() > 500, "MaxTetVolume relative 1e-3 refines the mesh");
  const double sphereVolume = 4.0 / 3.0 * vtkMath::Pi() * 1e-3;
  SB_CHECK(std::abs(volume - sphereVolume) < 0.05 * sphereVolume,
    "the tets fill the sphere (" << volume << " vs " << sphereVolume << ")");

  vtkUnstructuredGrid* moved = vtkUnstructuredGrid::SafeDownCast(body->GetOutput(0));
  SB_CHECK(moved && moved->GetNumberOfCells() == tets->GetNumberOfCells(),
    "the simulated body keeps the tets");
  SB_CHECK(std::abs(sbtest::FieldValue(moved, "SimulationTime") - 0.2) < 1e-9,
    "the body was simulated to t = 0.2");
  double bounds[6];
  moved->GetBounds(bounds);
  SB_CHECK(bounds[5] < 0.4 - 1e-3, "the body fell under gravity (top at " << bounds[5] << ")");
  for (double t : { 0.04, 0.08 })
  {
    SB_CHECK(body->UpdateTimeStep(t) == 1, "frame " << t);
  }

  // The mesher does not re-run when only the body's time changes, and does re-run on a change.
  const vtkMTimeType before = tets->GetMTime();
  body->UpdateTimeStep(0.12);
  SB_CHECK(tets->GetMTime() == before, "the mesher does not re-execute for a new time");
  mesher->PreserveBoundaryOn();
  mesher->Update();
  SB_CHECK(mesher->GetOutput()->GetMTime() != before, "a changed property re-meshes");
  SB_CHECK(Volumes(mesher->GetOutput()).second > 0.0, "PreserveBoundary: tets positive");
}

void DuplicatedCornersAreMerged()
{
  // The sphere stored as OBJ files store it: every triangle with its own three corner points.
  vtkNew<vtkSphereSource> sphere;
  sphere->Update();
  vtkPolyData* shared = sphere->GetOutput();
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> polys;
  for (vtkIdType c = 0; c < shared->GetNumberOfCells(); ++c)
  {
    const vtkIdType* ids = nullptr;
    vtkIdType n = 0;
    shared->GetCellPoints(c, n, ids);
    polys->InsertNextCell(static_cast<int>(n));
    for (vtkIdType k = 0; k < n; ++k)
    {
      polys->InsertCellPoint(points->InsertNextPoint(shared->GetPoint(ids[k])));
    }
  }
  vtkNew<vtkPolyData> soup;
  soup->SetPoints(points);
  soup->SetPolys(polys);
  vtkNew<vtkTetrahedralizeSurface> mesher;
  mesher->SetInputData(soup);
  vtkNew<sbtest::MessageCatcher> messages;
  messages->Observe(mesher);
  messages->Observe(mesher->GetExecutive());
  mesher->Update();
  SB_CHECK(messages->Errors.empty(), "duplicated corners: " << messages->AllErrors());
  SB_CHECK(AllTets(mesher->GetOutput()) && Volumes(mesher->GetOutput()).second > 0.0,
    "duplicated corners are merged and the sphere meshed");
}

void OpenSurfaceFails()
{
  vtkNew<vtkSphereSource> cap;
  cap->SetEndTheta(180.0); // half a sphere: open
  vtkNew<vtkTetrahedralizeSurface> mesher;
  mesher->SetInputConnection(cap->GetOutputPort());
  vtkNew<sbtest::MessageCatcher> messages;
  messages->Observe(mesher);
  messages->Observe(mesher->GetExecutive());
  mesher->Update();
  SB_CHECK(messages->ErrorContains("boundary edges"), "open surface: " << messages->AllErrors());
  SB_CHECK(mesher->GetOutput()->GetNumberOfCells() == 0, "open surface: empty output");

  // An empty input is an error, not a crash.
  vtkNew<vtkPolyData> empty;
  vtkNew<vtkTetrahedralizeSurface> mesher2;
  mesher2->SetInputData(empty);
  messages->Observe(mesher2);
  messages->Observe(mesher2->GetExecutive());
  messages->Clear();
  mesher2->Update();
  SB_CHECK(messages->ErrorContains("no polygons"), "empty input: " << messages->AllErrors());
}

template <typename Reader>
vtkUnstructuredGrid* Read(Reader* reader, const std::string& path, sbtest::MessageCatcher* messages)
{
  messages->Clear();
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

void Readers()
{
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "softbody_filter_test_meshing";
  fs::create_directories(dir);
  {
    std::ofstream(dir / "tet.node") << "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
    std::ofstream(dir / "tet.ele") << "1 4 0\n1 1 2 3 4\n";
    std::ofstream(dir / "tet.msh") << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n"
                                      "1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n$Elements\n"
                                      "2\n1 2 0 1 2 3\n2 4 0 1 2 3 4\n$EndElements\n";
    std::ofstream(dir / "cut.msh") << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0";
  }
  vtkNew<sbtest::MessageCatcher> messages;
  vtkNew<vtkTetGenReader> tetgen;
  vtkNew<vtkGmshReader> gmsh;
  for (vtkAlgorithm* a : { static_cast<vtkAlgorithm*>(tetgen), static_cast<vtkAlgorithm*>(gmsh) })
  {
    messages->Observe(a);
    messages->Observe(a->GetExecutive());
  }
  vtkUnstructuredGrid* g = Read(tetgen.Get(), (dir / "tet.ele").string(), messages);
  SB_CHECK(g->GetNumberOfPoints() == 4 && g->GetNumberOfCells() == 1 && AllTets(g),
    "TetGen reader: one tet " << messages->AllErrors());
  g = Read(gmsh.Get(), (dir / "tet.msh").string(), messages);
  SB_CHECK(g->GetNumberOfPoints() == 4 && g->GetNumberOfCells() == 1 && AllTets(g),
    "Gmsh reader: one tet " << messages->AllErrors());
  SB_CHECK(sbtest::FieldValue(g, "SkippedElements") == 1.0, "Gmsh reader: one triangle skipped");
  g = Read(gmsh.Get(), (dir / "cut.msh").string(), messages);
  SB_CHECK(messages->ErrorContains("cut.msh:6:"), "truncated .msh names its line: " << messages->AllErrors());
  SB_CHECK(g->GetNumberOfCells() == 0, "truncated .msh: empty output");
  g = Read(tetgen.Get(), (dir / "none.node").string(), messages);
  SB_CHECK(messages->ErrorContains("Cannot open"), "missing file: " << messages->AllErrors());
  fs::remove_all(dir);

  const fs::path data = SOFTBODY_SHARED_DATA_DIR;
  if (!fs::is_directory(data))
  {
    std::cout << "shared data not found at " << data << ": real meshes not read" << std::endl;
    return;
  }
  g = Read(tetgen.Get(), (data / "PositionBasedDynamics/armadillo_4k.node").string(), messages);
  SB_CHECK(g->GetNumberOfPoints() == 1180 && g->GetNumberOfCells() == 3717,
    "armadillo_4k: " << g->GetNumberOfPoints() << " points, " << g->GetNumberOfCells() << " tets");
  g = Read(gmsh.Get(), (data / "IPC/sphere5K.msh").string(), messages);
  SB_CHECK(g->GetNumberOfPoints() == 7034 && g->GetNumberOfCells() == 27792,
    "sphere5K: " << g->GetNumberOfPoints() << " points, " << g->GetNumberOfCells() << " tets");
  g = Read(gmsh.Get(), (data / "sofa/6_tetra_bad.msh").string(), messages);
  SB_CHECK(g->GetNumberOfPoints() == 17 && g->GetNumberOfCells() == 6,
    "6_tetra_bad: " << g->GetNumberOfPoints() << " points, " << g->GetNumberOfCells() << " tets");
}
} // namespace

int main()
{
  SurfaceToSimulatedBody();
  DuplicatedCornersAreMerged();
  OpenSurfaceFails();
  Readers();
  return sbtest::Result("filter.meshing");
}
