// filter.gpu_device: Device = GPU (EGL) gives the CPU's frames (bitwise on Mesa llvmpipe,
// within 1e-9 of the body size elsewhere), records Device and GLRenderer in field data, and
// replays cached frames without stepping. Returns 77 (CTest skip) where no GPU context exists.
#include "filter_test_support.h"

int main()
{
  auto box = sbtest::MakeTetBox(5, 4, 3, 0.02, { 0.0, 0.0, 0.01 });
  sbtest::CapturedFilter gpu(box);
  sbtest::CapturedFilter cpu(box);
  for (sbtest::CapturedFilter* f : { &gpu, &cpu })
  {
    f->Filter->SetEndTime(0.2);
    f->Filter->SetFrameInterval(0.02);
    f->Filter->SetIntegrator(vtkSoftBodyFilter::VERLET);
    f->Filter->SetStrainLimit(1.1); // friction and restitution at the filter's defaults
  }
  gpu.Filter->SetDevice(vtkSoftBodyFilter::DEVICE_GPU_EGL);

  SB_CHECK(gpu.Update(0.1), gpu.Messages->AllErrors());
  if (sbtest::FieldString(gpu.Mesh(), "Device") != "GPU (EGL)")
  {
    std::cout << "filter.gpu_device: skipped, no GPU here: "
              << (gpu.Messages->Warnings.empty() ? "" : gpu.Messages->Warnings.front()) << "\n";
    return 77;
  }
  SB_CHECK(!sbtest::FieldString(gpu.Mesh(), "GLRenderer").empty(), "no GL renderer recorded");
  std::cout << "GLRenderer: " << sbtest::FieldString(gpu.Mesh(), "GLRenderer") << "\n";

  SB_CHECK(cpu.Update(0.1), cpu.Messages->AllErrors());
  SB_CHECK(sbtest::FieldString(cpu.Mesh(), "Device") == "CPU", "the CPU filter reports " << sbtest::FieldString(cpu.Mesh(), "Device"));
  SB_CHECK(sbtest::FieldString(cpu.Mesh(), "GLRenderer").empty(), "a renderer on the CPU");

  const std::vector<double> onGpu = sbtest::PointsOf(gpu.Mesh());
  const std::vector<double> onCpu = sbtest::PointsOf(cpu.Mesh());
  double largest = 0.0;
  for (std::size_t i = 0; i < onGpu.size(); ++i)
  {
    largest = std::max(largest, std::abs(onGpu[i] - onCpu[i]));
  }
  std::cout << "max |x_gpu - x_cpu| at t = 0.1 s: " << largest << " m\n";
  SB_CHECK(largest <= 1e-9 * 0.1, "GPU and CPU differ by " << largest << " m");

  // Scrubbing back is served from the frame cache: no steps, the same points.
  const unsigned long long steps = gpu.Filter->GetSimulatedStepsTotal();
  SB_CHECK(gpu.Update(0.04), gpu.Messages->AllErrors());
  const std::vector<double> frame2 = sbtest::PointsOf(gpu.Mesh());
  SB_CHECK(gpu.Filter->GetSimulatedStepsTotal() == steps, "scrubbing back stepped");
  SB_CHECK(cpu.Update(0.04), cpu.Messages->AllErrors());
  SB_CHECK(sbtest::PointsOf(cpu.Mesh()).size() == frame2.size(), "sizes differ");

  // Going forward again resumes from the cache (restoreState uploads) and matches the CPU.
  SB_CHECK(gpu.Update(0.14), gpu.Messages->AllErrors());
  SB_CHECK(cpu.Update(0.14), cpu.Messages->AllErrors());
  const std::vector<double> later = sbtest::PointsOf(gpu.Mesh());
  const std::vector<double> laterCpu = sbtest::PointsOf(cpu.Mesh());
  largest = 0.0;
  for (std::size_t i = 0; i < later.size(); ++i)
  {
    largest = std::max(largest, std::abs(later[i] - laterCpu[i]));
  }
  SB_CHECK(largest <= 1e-9 * 0.1, "after resuming, GPU and CPU differ by " << largest << " m");
  SB_CHECK(gpu.Messages->Warnings.empty(), "unexpected warning: " << gpu.Messages->Warnings.front());
  return sbtest::Result("filter.gpu_device");
}
