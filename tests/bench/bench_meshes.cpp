#include "bench_meshes.h"

#include <algorithm>

#include "softbody/mesh/mesh_generators.h"

#include <tetgen.h>
#include <vtkCellArray.h>
#include <vtkCellTypes.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <fstream>
#include <iostream>

namespace softbody::bench
{
namespace
{

bool fileExists(const std::string& path)
{
  return std::ifstream(path).good();
}

TetMesh fromVtk(vtkUnstructuredGrid* grid)
{
  TetMesh mesh;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    double p[3];
    grid->GetPoint(i, p);
    mesh.points.emplace_back(p[0], p[1], p[2]);
  }
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    if (grid->GetCellType(c) != VTK_TETRA)
    {
      continue;
    }
    const vtkIdType* ids;
    vtkIdType count;
    grid->GetCellPoints(c, count, ids);
    mesh.tets.push_back({ static_cast<std::int32_t>(ids[0]), static_cast<std::int32_t>(ids[1]),
      static_cast<std::int32_t>(ids[2]), static_cast<std::int32_t>(ids[3]) });
  }
  return mesh;
}

/// TetGen's own .node/.ele loader (tetgenio), as the project's readers will use.
bool loadTetGen(const std::string& basePath, TetMesh& mesh)
{
  tetgenio io;
  std::vector<char> base(basePath.begin(), basePath.end());
  base.push_back('\0');
  if (!io.load_node(base.data()) || !io.load_tet(base.data()) || io.numberofcorners != 4)
  {
    return false;
  }
  for (int i = 0; i < io.numberofpoints; ++i)
  {
    mesh.points.emplace_back(io.pointlist[3 * i], io.pointlist[3 * i + 1], io.pointlist[3 * i + 2]);
  }
  const int first = io.firstnumber;
  for (int t = 0; t < io.numberoftetrahedra; ++t)
  {
    const int* c = io.tetrahedronlist + 4 * t;
    mesh.tets.push_back({ c[0] - first, c[1] - first, c[2] - first, c[3] - first });
  }
  return true;
}

} // namespace

std::vector<NamedMesh> generatedMeshes(bool smoke)
{
  // Box sizes chosen for ~1k, ~10k, ~50k and ~150k tets (6 per cube).
  struct Size
  {
    int nx, ny, nz;
  };
  const std::vector<Size> sizes = smoke ? std::vector<Size>{ { 6, 6, 5 }, { 12, 12, 12 } }
                                        : std::vector<Size>{ { 6, 6, 5 }, { 12, 12, 12 },
                                            { 20, 20, 21 }, { 30, 30, 28 } };
  std::vector<NamedMesh> meshes;
  for (const Size& s : sizes)
  {
    NamedMesh m;
    m.mesh = makeTetBox(s.nx, s.ny, s.nz, 0.01);
    m.name = "box_" + std::to_string(m.mesh.tets.size());
    meshes.push_back(std::move(m));
  }
  return meshes;
}

std::vector<NamedMesh> sharedMeshes(const std::string& dataDir)
{
  std::vector<NamedMesh> meshes;
  const std::string armadillo = dataDir + "/PositionBasedDynamics/armadillo_4k";
  const std::string sofaVtu = dataDir + "/sofa/Armadillo_Tetra_4406.vtu";
  const std::string sofaVtk = dataDir + "/sofa/cylinderPDMS12724Vol.vtk";
  if (!fileExists(armadillo + ".node"))
  {
    std::cout << "note: " << dataDir << " not found or incomplete; public meshes skipped\n";
    return meshes;
  }
  NamedMesh a{ "armadillo_4k", {} };
  if (loadTetGen(armadillo, a.mesh))
  {
    meshes.push_back(std::move(a));
  }
  if (fileExists(sofaVtu))
  {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(sofaVtu.c_str());
    reader->Update();
    meshes.push_back({ "Armadillo_Tetra_4406", fromVtk(reader->GetOutput()) });
  }
  if (fileExists(sofaVtk))
  {
    vtkNew<vtkUnstructuredGridReader> reader;
    reader->SetFileName(sofaVtk.c_str());
    reader->Update();
    meshes.push_back({ "cylinderPDMS12724Vol", fromVtk(reader->GetOutput()) });
  }
  return meshes;
}

SceneSettings landingScene(const TetMesh& mesh, bool floor, double strainLimit)
{
  double lowest = 1e300;
  for (const Vec3& p : mesh.points)
  {
    lowest = std::min(lowest, p.z());
  }
  SceneSettings scene;
  scene.floorEnabled = floor;
  scene.floor.origin = Vec3(0, 0, lowest - 1e-3);
  scene.strainLimit = strainLimit;
  return scene;
}

double maxDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b)
{
  double largest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    largest = std::max(largest, (a[i] - b[i]).norm());
  }
  return largest;
}

} // namespace softbody::bench
