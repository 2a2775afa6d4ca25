// filter.abort: progress is reported over the frames to simulate, an abort requested midway
// stops the run cleanly (empty output, no error, no crash), keeps the frames completed before
// it, and the next request resumes from them to the same bits as an uninterrupted run.
#include "filter_test_support.h"

namespace
{
constexpr double kInterval = 0.02;

/// Records progress values and, when armed, requests an abort once progress passes a threshold.
class AbortAtProgress : public vtkCommand
{
public:
  static AbortAtProgress* New() { return new AbortAtProgress; }
  void Execute(vtkObject* caller, unsigned long, void* callData) override
  {
    const double progress = *static_cast<double*>(callData);
    this->Values.push_back(progress);
    if (this->Armed && progress >= this->Threshold)
    {
      static_cast<vtkAlgorithm*>(caller)->AbortExecuteOn();
      this->Armed = false;
    }
  }
  bool Armed = false;
  double Threshold = 0.5;
  std::vector<double> Values;
};
} // namespace

int main()
{
  auto box = sbtest::MakeTetBox(3, 3, 3, 0.05, { 0.0, 0.0, 1.0 });

  // Reference: frame 10 without interruption.
  sbtest::CapturedFilter reference(box);
  reference.Filter->SetFrameInterval(kInterval);
  SB_CHECK(reference.Update(10 * kInterval), reference.Messages->AllErrors());
  const std::vector<double> expected = sbtest::PointsOf(reference.Mesh());
  const unsigned long long referenceSteps = reference.Filter->GetSimulatedStepsTotal();

  sbtest::CapturedFilter f(box);
  f.Filter->SetFrameInterval(kInterval);
  vtkNew<AbortAtProgress> observer;
  f.Filter->AddObserver(vtkCommand::ProgressEvent, observer);

  // Progress rises monotonically to 1 on an uninterrupted request.
  SB_CHECK(f.Update(2 * kInterval), f.Messages->AllErrors());
  SB_CHECK(!observer->Values.empty() && observer->Values.back() == 1.0, "progress ends at 1");
  SB_CHECK(std::is_sorted(observer->Values.begin(), observer->Values.end()), "progress is monotonic");

  // Abort halfway through frames 3..10.
  observer->Values.clear();
  observer->Armed = true;
  f.Update(10 * kInterval);
  SB_CHECK(!observer->Armed, "the abort was requested");
  SB_CHECK(f.Messages->Errors.empty(), "an abort is not an error: " << f.Messages->AllErrors());
  SB_CHECK(f.Mesh()->GetNumberOfPoints() == 0, "an aborted request outputs nothing");
  const int cached = f.Filter->GetNumberOfCachedFrames();
  SB_CHECK(cached > 3 && cached < 11, "frames completed before the abort stay cached: " << cached);
  const unsigned long long stepsAtAbort = f.Filter->GetSimulatedStepsTotal();
  SB_CHECK(stepsAtAbort < referenceSteps, "the aborted run stopped early");

  // The next request resumes from the cached frames and lands on the uninterrupted result.
  f.Filter->AbortExecuteOff();
  SB_CHECK(f.Update(10 * kInterval), f.Messages->AllErrors());
  SB_CHECK(sbtest::BitwiseEqual(sbtest::PointsOf(f.Mesh()), expected), "resumed run matches bitwise");
  SB_CHECK(f.Filter->GetSimulatedStepsTotal() - stepsAtAbort < referenceSteps,
    "the resumed run did not start over from frame 0");
  SB_CHECK(f.Filter->GetNumberOfCachedFrames() == 11, "frames 0..10 cached");

  return sbtest::Result("filter.abort");
}
