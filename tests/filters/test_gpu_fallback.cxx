// filter.gpu_fallback: with Device = GPU (EGL) where no EGL driver can be found, the filter
// warns why, simulates on the CPU (same frames as Device = CPU) and records Device = "CPU" and
// the reason in Warnings. CTest runs it with __EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent, which
// leaves glvnd without any EGL vendor (EGL_PLATFORM tricks do not: the backend names its
// platforms explicitly).
#include "filter_test_support.h"

int main()
{
  auto box = sbtest::MakeTetBox(4, 3, 3, 0.02, { 0.0, 0.0, 0.01 });
  sbtest::CapturedFilter gpu(box);
  sbtest::CapturedFilter cpu(box);
  for (sbtest::CapturedFilter* f : { &gpu, &cpu })
  {
    f->Filter->SetEndTime(0.1);
    f->Filter->SetFrameInterval(0.02);
  }
  gpu.Filter->SetDevice(vtkSoftBodyFilter::DEVICE_GPU_EGL);

  SB_CHECK(gpu.Update(0.06), gpu.Messages->AllErrors());
  SB_CHECK(gpu.Messages->Errors.empty(), "the fallback must not be an error");
  SB_CHECK(gpu.Messages->Warnings.size() == 1, gpu.Messages->Warnings.size() << " warnings");
  const std::string warning = gpu.Messages->Warnings.empty() ? "" : gpu.Messages->Warnings.front();
  std::cout << "warning: " << warning << "\n";
  SB_CHECK(warning.find("GPU (EGL) is unavailable, simulating on the CPU") != std::string::npos,
    "the warning does not say what happened: " << warning);
  SB_CHECK(warning.find("EGL") != std::string::npos, "the warning does not say why");
  SB_CHECK(sbtest::FieldString(gpu.Mesh(), "Device") == "CPU", "Device = " << sbtest::FieldString(gpu.Mesh(), "Device"));
  SB_CHECK(sbtest::FieldString(gpu.Mesh(), "GLRenderer").empty(), "a renderer without a GPU");
  auto* warnings = vtkStringArray::SafeDownCast(gpu.Mesh()->GetFieldData()->GetAbstractArray("Warnings"));
  // The caught message carries VTK's "Warning: In ..." prefix; the field holds the text alone.
  const std::string recorded = warnings && warnings->GetNumberOfValues() > 0
    ? warnings->GetValue(warnings->GetNumberOfValues() - 1)
    : std::string();
  SB_CHECK(!recorded.empty() && warning.find(recorded) != std::string::npos,
    "the reason is not in the Warnings field data: " << recorded);

  SB_CHECK(cpu.Update(0.06), cpu.Messages->AllErrors());
  SB_CHECK(sbtest::PointsOf(gpu.Mesh()) == sbtest::PointsOf(cpu.Mesh()),
    "the fallback does not give the CPU's frames");

  // Said once per set-up, not on every frame.
  gpu.Messages->Clear();
  SB_CHECK(gpu.Update(0.08), gpu.Messages->AllErrors());
  SB_CHECK(gpu.Messages->Warnings.empty(), "the warning repeats on every frame");
  return sbtest::Result("filter.gpu_fallback");
}
