#include "bench_meshes.h"

#include <algorithm>

#include "softbody/mesh/mesh_generators.h"
#include "softbody/mesh/mesh_io.h"
#include "softbody/mesh/tetrahedralize.h"

#include <tetgen.h>
#include <vtkCellArray.h>
#include <vtkCellTypes.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

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

std::vector<NamedMesh> sharedMeshes(const std::string& dataDir, bool smoke)
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
  if (!smoke)
  {
    for (const char* name : { "bunny", "sphere5K", "Armadillo13K" })
    {
      const std::string path = dataDir + "/IPC/" + name + ".msh";
      if (!fileExists(path))
      {
        std::cout << "note: " << path << " not found; skipped\n";
        continue;
      }
      meshes.push_back({ std::string("IPC_") + name, readGmshMesh(path) });
    }
  }
  return meshes;
}

void readObjSurface(const std::string& path, std::vector<Vec3>& points,
  std::vector<std::array<std::int32_t, 3>>& triangles)
{
  std::ifstream in(path);
  if (!in)
  {
    throw std::runtime_error("cannot open " + path);
  }
  std::string line;
  while (std::getline(in, line))
  {
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind == "v")
    {
      double x = 0, y = 0, z = 0;
      words >> x >> y >> z;
      points.emplace_back(x, y, z);
    }
    else if (kind == "f")
    {
      std::vector<std::int32_t> corners;
      std::string corner;
      while (words >> corner)
      {
        const long index = std::stol(corner.substr(0, corner.find('/')));
        corners.push_back(static_cast<std::int32_t>(index > 0 ? index - 1 : long(points.size()) + index));
      }
      for (std::size_t k = 2; k < corners.size(); ++k)
      {
        triangles.push_back({ corners[0], corners[k - 1], corners[k] });
      }
    }
  }
}

namespace
{
/// An icosphere: the icosahedron with each triangle split in four `levels` times, on the unit
/// sphere, outward oriented.
void icosphere(int levels, std::vector<Vec3>& points, std::vector<std::array<std::int32_t, 3>>& triangles)
{
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  points = { { -1, t, 0 }, { 1, t, 0 }, { -1, -t, 0 }, { 1, -t, 0 }, { 0, -1, t }, { 0, 1, t },
    { 0, -1, -t }, { 0, 1, -t }, { t, 0, -1 }, { t, 0, 1 }, { -t, 0, -1 }, { -t, 0, 1 } };
  for (Vec3& p : points)
  {
    p.normalize();
  }
  triangles = { { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 }, { 0, 7, 10 }, { 0, 10, 11 }, { 1, 5, 9 },
    { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 }, { 7, 1, 8 }, { 3, 9, 4 }, { 3, 4, 2 }, { 3, 2, 6 },
    { 3, 6, 8 }, { 3, 8, 9 }, { 4, 9, 5 }, { 2, 4, 11 }, { 6, 2, 10 }, { 8, 6, 7 }, { 9, 8, 1 } };
  for (int level = 0; level < levels; ++level)
  {
    std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> middle;
    auto mid = [&](std::int32_t a, std::int32_t b) {
      const auto key = std::minmax(a, b);
      auto it = middle.find(key);
      if (it != middle.end())
      {
        return it->second;
      }
      points.push_back((points[std::size_t(a)] + points[std::size_t(b)]).normalized());
      const auto index = static_cast<std::int32_t>(points.size() - 1);
      middle[key] = index;
      return index;
    };
    std::vector<std::array<std::int32_t, 3>> finer;
    for (const auto& tri : triangles)
    {
      const std::int32_t a = mid(tri[0], tri[1]), b = mid(tri[1], tri[2]), c = mid(tri[2], tri[0]);
      finer.push_back({ tri[0], a, c });
      finer.push_back({ tri[1], b, a });
      finer.push_back({ tri[2], c, b });
      finer.push_back({ a, b, c });
    }
    triangles = std::move(finer);
  }
}

NamedMesh tetgenOfSurface(const std::string& name, const std::string& path)
{
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;
  readObjSurface(path, points, triangles);
  return { name, tetrahedralizeSurface(points, triangles, TetrahedralizeOptions{}) };
}
} // namespace

TetMesh ellipsoidMesh(double targetTets)
{
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;
  icosphere(4, points, triangles);
  for (Vec3& p : points)
  {
    p = Vec3(0.20 * p.x(), 0.12 * p.y(), 0.08 * p.z() + 0.10);
  }
  // TetGen's tets average about 0.38 of the volume bound here (measured); one correction
  // step lands within a few percent of the target.
  const double volume = 4.0 / 3.0 * M_PI * 0.20 * 0.12 * 0.08;
  TetrahedralizeOptions options;
  options.maxTetVolume = volume / targetTets / 0.38;
  TetMesh mesh = tetrahedralizeSurface(points, triangles, options);
  const double ratio = double(mesh.tets.size()) / targetTets;
  if (std::abs(ratio - 1.0) > 0.05)
  {
    options.maxTetVolume *= ratio;
    mesh = tetrahedralizeSurface(points, triangles, options);
  }
  return mesh;
}

std::vector<NamedMesh> realMeshes(const std::string& dataDir, bool smoke)
{
  std::vector<NamedMesh> meshes;
  const std::string spot = dataDir + "/keenan-spot/spot_triangulated.obj";
  const std::string bunny = dataDir + "/PositionBasedDynamics/bunny_10k.obj";
  for (const auto& [name, path, inSmoke] : { std::tuple{ "tetgen_spot", spot, true },
         std::tuple{ "tetgen_bunny_10k", bunny, false } })
  {
    if (smoke && !inSmoke)
    {
      continue;
    }
    if (!fileExists(path))
    {
      std::cout << "note: " << path << " not found; " << name << " skipped\n";
      continue;
    }
    try
    {
      meshes.push_back(tetgenOfSurface(name, path));
    }
    catch (const std::exception& error)
    {
      std::cout << "note: " << name << " not meshed: " << error.what() << "\n";
    }
  }
  if (!smoke)
  {
    meshes.push_back({ "ellipsoid180k", ellipsoidMesh(180000.0) });
  }
  return meshes;
}

std::vector<NamedMesh> benchmarkMeshes(bool smoke, const std::string& dataDir, const std::string& spec)
{
  if (!spec.empty())
  {
    return { meshFromSpec(spec, dataDir) };
  }
  std::vector<NamedMesh> meshes = generatedMeshes(smoke);
  for (auto& m : sharedMeshes(dataDir, smoke))
  {
    meshes.push_back(std::move(m));
  }
  for (auto& m : realMeshes(dataDir, smoke))
  {
    meshes.push_back(std::move(m));
  }
  return meshes;
}

NamedMesh meshFromSpec(const std::string& spec, const std::string& dataDir)
{
  auto endsWith = [&](const std::string& suffix) {
    return spec.size() >= suffix.size() && spec.compare(spec.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (spec.rfind("ellipsoid", 0) == 0 && endsWith("k"))
  {
    const double thousands = std::stod(spec.substr(9, spec.size() - 10));
    return { spec, ellipsoidMesh(1000.0 * thousands) };
  }
  if (fileExists(spec) || fileExists(spec + ".node"))
  {
    std::string base = spec;
    const std::size_t slash = base.find_last_of('/');
    const std::string file = slash == std::string::npos ? base : base.substr(slash + 1);
    if (endsWith(".msh"))
    {
      return { file, readGmshMesh(spec) };
    }
    if (endsWith(".obj"))
    {
      return tetgenOfSurface("tetgen_" + file, spec);
    }
    return { file, readTetGenMesh(spec) };
  }
  for (bool smoke : { true, false })
  {
    for (auto& m : generatedMeshes(smoke))
    {
      if (m.name == spec)
      {
        return m;
      }
    }
  }
  for (auto& m : sharedMeshes(dataDir, false))
  {
    if (m.name == spec || m.name == "IPC_" + spec)
    {
      return m;
    }
  }
  for (auto& m : realMeshes(dataDir, true))
  {
    if (m.name == spec)
    {
      return m;
    }
  }
  if (spec == "tetgen_bunny_10k")
  {
    return tetgenOfSurface(spec, dataDir + "/PositionBasedDynamics/bunny_10k.obj");
  }
  throw std::runtime_error("no mesh named " + spec + " (a benchmark mesh's name, ellipsoidNk, "
                           "or a .node/.ele, .msh or .obj file)");
}

const NamedMesh* referenceBox(const std::vector<NamedMesh>& meshes)
{
  const NamedMesh* box = nullptr;
  for (const NamedMesh& m : meshes)
  {
    if (m.name.rfind("box_", 0) == 0 && (!box || m.mesh.tets.size() > box->mesh.tets.size()))
    {
      box = &m;
    }
  }
  return box;
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
  // A contact margin well under the 1 mm gap, so the body lands rather than starting inside
  // the automatic one (a tenth of the mean surface edge).
  scene.collisions.margin = 1e-4;
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

std::string blowUpCause(const std::string& divergenceMessage, const std::string& otherwise)
{
  const std::string quoted = "rho g H / E = ";
  const std::size_t at = divergenceMessage.find(quoted);
  if (divergenceMessage.find("cannot carry its own weight") == std::string::npos || at == std::string::npos)
  {
    return otherwise;
  }
  const std::size_t start = at + quoted.size();
  const std::string strain = divergenceMessage.substr(start, divergenceMessage.find(' ', start) - start);
  return "collapsed under its own weight (rho g H / E = " + strain + ")";
}

} // namespace softbody::bench
