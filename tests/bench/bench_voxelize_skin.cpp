// Voxelization and skinning cost against particle and vertex counts: both must scale linearly
// (the PBD thesis's all-pairs neighbor search and 3-nearest-particle skinning did not).
//
// 1. Soft Body Voxelize on a sphere (vtkSphereSource, 64 x 64) at resolutions 10 .. 80: wall
//    time, particles, links, and time per grid node and per particle.
// 2. Skinning onto a fixed lattice (resolution 40) surfaces of growing vertex counts: the
//    binding (once) and one application (every frame), time per vertex.
// Constant time per item across a 64x (voxelize) or 256x (skinning) range is linear scaling.
//
// Beside the CSV, a Markdown file with both tables under the headings "Voxelization" and
// "Skinning" (docs/performance.md's tables, scripts/update_docs_tables.py).
//
// Usage: bench_voxelize_skin [--smoke] [--csv file]
#include "bench_options.h"

#include "vtkSoftBodyVoxelize.h"

#include "vtkIntArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/lattice/lattice.h"
#include "softbody/lattice/skinning.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

using namespace softbody;

namespace
{
double secondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

vtkSmartPointer<vtkPolyData> sphere(int resolution)
{
  vtkNew<vtkSphereSource> source;
  source->SetRadius(0.5);
  source->SetThetaResolution(resolution);
  source->SetPhiResolution(resolution);
  source->Update();
  vtkSmartPointer<vtkPolyData> out = source->GetOutput();
  return out;
}

/// The core lattice of a Soft Body Voxelize output (as the Soft Body filter rebuilds it).
Lattice latticeOf(vtkUnstructuredGrid* grid)
{
  Lattice lattice;
  vtkFieldData* field = grid->GetFieldData();
  field->GetArray("LatticeOrigin")->GetTuple(0, lattice.grid.origin.data());
  lattice.grid.spacing = field->GetArray("LatticeSpacing")->GetTuple1(0);
  for (int a = 0; a < 3; ++a)
  {
    lattice.grid.nodes[std::size_t(a)] = int(field->GetArray("LatticeDimensions")->GetComponent(0, a));
  }
  lattice.particleOfNode.assign(lattice.grid.nodeCount(), -1);
  vtkDataArray* index = grid->GetPointData()->GetArray("LatticeIndex");
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    Vec3 x;
    grid->GetPoint(p, x.data());
    lattice.points.push_back(x);
    lattice.particleOfNode[lattice.grid.nodeIndex(int(index->GetComponent(p, 0)),
      int(index->GetComponent(p, 1)), int(index->GetComponent(p, 2)))] = std::int32_t(p);
  }
  return lattice;
}
} // namespace

int main(int argc, char** argv)
{
  const bench::Options options = bench::parseOptions(argc, argv, "bench_voxelize_skin", "bench_voxelize_skin.csv");
  std::ofstream csv(options.csv);
  csv << "part,size,items,seconds,ns_per_item\n";
  std::ofstream table(bench::tableBeside(options.csv));
  table << "# Voxelization\n\n| resolution | grid nodes | particles | links | seconds | us per particle |\n"
           "|---:|---:|---:|---:|---:|---:|\n";
  char row[256];

  std::printf("Soft Body Voxelize on a sphere (64 x 64 triangles' source)\n");
  std::printf("%10s %12s %12s %12s %10s %14s %14s\n", "resolution", "grid nodes", "particles",
    "links", "seconds", "ns/node", "ns/particle");
  const vtkSmartPointer<vtkPolyData> surface = sphere(64);
  vtkSmartPointer<vtkUnstructuredGrid> lattice40;
  const std::vector<int> resolutions = options.smoke ? std::vector<int>{ 8, 16 } : std::vector<int>{ 10, 20, 40, 80 };
  for (int resolution : resolutions)
  {
    vtkNew<vtkSoftBodyVoxelize> voxelize;
    voxelize->SetInputData(surface);
    voxelize->SetResolution(resolution);
    const auto start = std::chrono::steady_clock::now();
    voxelize->Update();
    const double seconds = secondsSince(start);
    vtkUnstructuredGrid* out = voxelize->GetOutput();
    const double nodes = out->GetFieldData()->GetArray("LatticeDimensions")->GetComponent(0, 0) *
      out->GetFieldData()->GetArray("LatticeDimensions")->GetComponent(0, 1) *
      out->GetFieldData()->GetArray("LatticeDimensions")->GetComponent(0, 2);
    std::printf("%10d %12.0f %12lld %12lld %10.4f %14.1f %14.1f\n", resolution, nodes,
      static_cast<long long>(out->GetNumberOfPoints()), static_cast<long long>(out->GetNumberOfCells()),
      seconds, 1e9 * seconds / nodes, 1e9 * seconds / double(out->GetNumberOfPoints()));
    std::snprintf(row, sizeof row, "| %d | %.0f | %lld | %lld | %.3g | %.3g |\n", resolution, nodes,
      static_cast<long long>(out->GetNumberOfPoints()), static_cast<long long>(out->GetNumberOfCells()),
      seconds, 1e6 * seconds / double(out->GetNumberOfPoints()));
    table << row;
    csv << "voxelize," << resolution << ',' << out->GetNumberOfPoints() << ',' << seconds << ','
        << 1e9 * seconds / double(out->GetNumberOfPoints()) << '\n';
    if (out->GetNumberOfPoints() == 0 || out->GetNumberOfCells() == 0)
    {
      std::fprintf(stderr, "error: voxelizing at resolution %d gave no particles or links\n", resolution);
      return 1;
    }
    if (resolution == (options.smoke ? 16 : 40))
    {
      lattice40 = vtkSmartPointer<vtkUnstructuredGrid>::New();
      lattice40->DeepCopy(out);
    }
  }

  const Lattice lattice = latticeOf(lattice40);
  std::printf("\nSkinning onto a lattice of %zu particles\n", lattice.points.size());
  std::printf("%10s %12s %12s %14s %12s %14s\n", "sphere res", "vertices", "bind [s]", "bind ns/vert",
    "apply [s]", "apply ns/vert");
  table << "\n# Skinning\n\n| sphere resolution | vertices | lattice particles | bind ms | bind ns per vertex "
           "| apply ms | apply ns per vertex |\n|---:|---:|---:|---:|---:|---:|---:|\n";
  const std::vector<int> surfaces = options.smoke ? std::vector<int>{ 16, 32 } : std::vector<int>{ 32, 64, 128, 256, 512 };
  for (int resolution : surfaces)
  {
    const vtkSmartPointer<vtkPolyData> render = sphere(resolution);
    std::vector<Vec3> vertices(std::size_t(render->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < render->GetNumberOfPoints(); ++i)
    {
      render->GetPoint(i, vertices[std::size_t(i)].data());
    }
    auto start = std::chrono::steady_clock::now();
    const Skin skin = bindToLattice(lattice, vertices);
    const double bind = secondsSince(start);
    std::vector<Vec3> moved;
    const int repeats = 20;
    start = std::chrono::steady_clock::now();
    for (int r = 0; r < repeats; ++r)
    {
      applySkin(skin, lattice.points, moved);
    }
    const double apply = secondsSince(start) / repeats;
    const double n = double(vertices.size());
    // The run is checked, not only timed: every vertex bound, and the undeformed lattice gives
    // the surface back (trilinear weights reproduce positions exactly).
    double worst = 0.0;
    for (std::size_t v = 0; v < vertices.size(); ++v)
    {
      worst = std::max(worst, (moved[v] - vertices[v]).norm());
    }
    if (skin.vertexCount() != vertices.size() || moved.size() != vertices.size() || !(worst < 1e-9))
    {
      std::fprintf(stderr, "error: skinning %zu vertices gave %zu back, off by up to %g\n",
        vertices.size(), moved.size(), worst);
      return 1;
    }
    std::printf("%10d %12zu %12.5f %14.1f %12.6f %14.2f\n", resolution, vertices.size(), bind,
      1e9 * bind / n, apply, 1e9 * apply / n);
    std::snprintf(row, sizeof row, "| %d | %zu | %zu | %.3g | %.3g | %.3g | %.3g |\n", resolution,
      vertices.size(), lattice.points.size(), 1e3 * bind, 1e9 * bind / n, 1e3 * apply, 1e9 * apply / n);
    table << row;
    csv << "bind," << resolution << ',' << vertices.size() << ',' << bind << ',' << 1e9 * bind / n << '\n';
    csv << "apply," << resolution << ',' << vertices.size() << ',' << apply << ',' << 1e9 * apply / n << '\n';
  }
  std::printf("\nCSV: %s\n", options.csv.c_str());
  return 0;
}
