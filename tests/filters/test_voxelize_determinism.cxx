// filter.voxelize_determinism: Soft Body Voxelize gives the same particles, bit for bit, on
// every run and at any thread count, on a raw .obj as read (each corner of each triangle its own
// point, as OBJ files with per-corner normals give). Reads ../shared/data; exits 77 (skipped)
// when the files are absent.
#include "filter_test_support.h"

#include "vtkOBJReader.h"
#include "vtkPolyData.h"
#include "vtkSoftBodyVoxelize.h"

#include <filesystem>

namespace
{
std::vector<double> Voxelize(vtkPolyData* surface, int threads, int resolution)
{
  vtkNew<vtkSoftBodyVoxelize> voxelize;
  voxelize->SetInputData(surface);
  voxelize->SetResolution(resolution);
  voxelize->SetNumberOfThreads(threads);
  voxelize->Update();
  return sbtest::PointsOf(voxelize->GetOutput());
}
} // namespace

int main()
{
  const std::filesystem::path data = SOFTBODY_SHARED_DATA_DIR;
  const char* files[] = { "PositionBasedDynamics/bunny_10k.obj", "keenan-spot/spot_triangulated.obj" };
  int found = 0;
  for (const char* file : files)
  {
    const std::filesystem::path path = data / file;
    if (!std::filesystem::exists(path))
    {
      std::cout << "skipping " << path << ": not found" << std::endl;
      continue;
    }
    ++found;
    vtkNew<vtkOBJReader> reader;
    reader->SetFileName(path.string().c_str());
    reader->Update();
    vtkPolyData* raw = reader->GetOutput();
    for (int resolution : { 20, 37 })
    {
      const std::vector<double> reference = Voxelize(raw, 1, resolution);
      std::cout << file << " at Resolution " << resolution << ": " << reference.size() / 3
                << " particles" << std::endl;
      SB_CHECK(!reference.empty(), file << ": particles expected");
      for (int run = 0; run < 6; ++run)
      {
        const int threads = run % 2 == 0 ? 2 : 1 + run; // 2, 2, 2, 4, 2, 6
        const std::vector<double> again = Voxelize(raw, threads, resolution);
        SB_CHECK(sbtest::BitwiseEqual(reference, again),
          file << " Resolution " << resolution << " run " << run << " with " << threads
               << " threads: " << again.size() / 3 << " particles, 1 thread gave "
               << reference.size() / 3);
      }
    }
  }
  if (found == 0)
  {
    std::cout << "shared data not found in " << data << ": skipped" << std::endl;
    return 77;
  }
  return sbtest::Result("filter.voxelize_determinism");
}
