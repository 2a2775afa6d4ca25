// filter.time_protocol: the filter advertises its own frame times (0..EndTime by FrameInterval,
// EndTime appended when off the grid), stamps DATA_TIME_STEP on both outputs, clamps requests,
// and keeps the requested time away from a temporal input (which must not re-execute per frame).
#include "filter_test_support.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGridAlgorithm.h"

namespace
{
using SDDP = vtkStreamingDemandDrivenPipeline;

/// A source that advertises times of its own (10 and 20) and counts its executions.
class TemporalBoxSource : public vtkUnstructuredGridAlgorithm
{
public:
  static TemporalBoxSource* New();
  vtkTypeMacro(TemporalBoxSource, vtkUnstructuredGridAlgorithm)
  int Executions = 0;

protected:
  TemporalBoxSource() { this->SetNumberOfInputPorts(0); }
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    const double times[2] = { 10.0, 20.0 };
    const double range[2] = { 10.0, 20.0 };
    out->GetInformationObject(0)->Set(SDDP::TIME_STEPS(), times, 2);
    out->GetInformationObject(0)->Set(SDDP::TIME_RANGE(), range, 2);
    return 1;
  }
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    ++this->Executions;
    vtkUnstructuredGrid::GetData(out)->ShallowCopy(sbtest::MakeTetBox(2, 2, 2, 0.1, { 0, 0, 1 }));
    return 1;
  }
};
vtkStandardNewMacro(TemporalBoxSource);

std::vector<double> TimeSteps(vtkInformation* info)
{
  std::vector<double> steps;
  if (info->Has(SDDP::TIME_STEPS()))
  {
    const double* values = info->Get(SDDP::TIME_STEPS());
    steps.assign(values, values + info->Length(SDDP::TIME_STEPS()));
  }
  return steps;
}

void CheckAdvertised(double endTime, double interval, const std::vector<double>& expected)
{
  auto box = sbtest::MakeTetBox(1, 1, 1, 0.1, { 0, 0, 0 });
  vtkNew<vtkSoftBodyFilter> filter;
  filter->SetInputData(box);
  filter->SetEndTime(endTime);
  filter->SetFrameInterval(interval);
  filter->UpdateInformation();
  for (int port = 0; port < 2; ++port)
  {
    vtkInformation* info = filter->GetOutputInformation(port);
    const std::vector<double> steps = TimeSteps(info);
    SB_CHECK(steps.size() == expected.size(),
      "EndTime " << endTime << ", FrameInterval " << interval << ", port " << port << ": "
                 << steps.size() << " steps, expected " << expected.size());
    for (std::size_t i = 0; i < std::min(steps.size(), expected.size()); ++i)
    {
      SB_CHECK(std::abs(steps[i] - expected[i]) <= 1e-12, "step " << i << " is " << steps[i]
                                                                  << ", expected " << expected[i]);
    }
    SB_CHECK(!steps.empty() && steps.back() == endTime, "last step must be EndTime exactly");
    const double* range = info->Get(SDDP::TIME_RANGE());
    SB_CHECK(range && range[0] == 0.0 && range[1] == endTime, "TIME_RANGE must be [0, EndTime]");
  }
}
} // namespace

int main()
{
  // On the grid, off the grid (EndTime appended), and the defaults (3 s at 25 fps).
  CheckAdvertised(1.0, 0.25, { 0.0, 0.25, 0.5, 0.75, 1.0 });
  CheckAdvertised(1.0, 0.3, { 0.0, 0.3, 0.6, 0.9, 1.0 });
  std::vector<double> defaults;
  for (int k = 0; k <= 75; ++k)
  {
    defaults.push_back(k * 0.04);
  }
  defaults.back() = 3.0;
  CheckAdvertised(3.0, 0.04, defaults);

  // DATA_TIME_STEP on both ports, SimulationTime in the field data, clamping.
  {
    auto box = sbtest::MakeTetBox(2, 2, 2, 0.1, { 0, 0, 1 });
    sbtest::CapturedFilter f(box);
    f.Filter->SetEndTime(1.0);
    f.Filter->SetFrameInterval(0.25);
    SB_CHECK(f.Update(0.5), f.Messages->AllErrors());
    for (int port = 0; port < 2; ++port)
    {
      vtkDataObject* out = f.Filter->GetOutputDataObject(port);
      SB_CHECK(out->GetInformation()->Has(vtkDataObject::DATA_TIME_STEP()) &&
          out->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()) == 0.5,
        "DATA_TIME_STEP of port " << port << " must be 0.5");
    }
    SB_CHECK(std::abs(sbtest::FieldValue(f.Mesh(), "SimulationTime") - 0.5) < 1e-12,
      "SimulationTime is " << sbtest::FieldValue(f.Mesh(), "SimulationTime"));
    SB_CHECK(vtkPolyData::SafeDownCast(f.Filter->GetOutputDataObject(vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Particles)))->GetNumberOfVerts() ==
        box->GetNumberOfPoints(),
      "particles: one vertex per point");

    // Off-grid time: simulated, but only the grid frames before it are cached (0, 1).
    SB_CHECK(f.Update(0.4), f.Messages->AllErrors());
    SB_CHECK(std::abs(sbtest::FieldValue(f.Mesh(), "SimulationTime") - 0.4) < 1e-12,
      "off-grid SimulationTime is " << sbtest::FieldValue(f.Mesh(), "SimulationTime"));
    SB_CHECK(f.Filter->GetNumberOfCachedFrames() == 3,
      "frames 0, 1, 2 cached (from the 0.5 request), got " << f.Filter->GetNumberOfCachedFrames());

    // Beyond EndTime: clamped.
    SB_CHECK(f.Update(7.0), f.Messages->AllErrors());
    SB_CHECK(f.Mesh()->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()) == 1.0,
      "a request past EndTime is clamped to EndTime");
    SB_CHECK(std::abs(sbtest::FieldValue(f.Mesh(), "SimulationTime") - 1.0) < 1e-12,
      "SimulationTime at the clamped end");
    SB_CHECK(f.Messages->Errors.empty(), f.Messages->AllErrors());
  }

  // A temporal input: its times are replaced by ours and it executes once, not once per frame.
  {
    vtkNew<TemporalBoxSource> source;
    vtkNew<vtkSoftBodyFilter> filter;
    filter->SetInputConnection(source->GetOutputPort());
    filter->SetEndTime(0.5);
    filter->SetFrameInterval(0.1);
    filter->UpdateInformation();
    const std::vector<double> steps = TimeSteps(filter->GetOutputInformation(0));
    SB_CHECK(steps.size() == 6 && steps.front() == 0.0 && steps.back() == 0.5,
      "the input's times (10, 20) must not leak through; got " << steps.size() << " steps");
    for (double t : { 0.1, 0.3, 0.2, 0.5 })
    {
      SB_CHECK(filter->UpdateTimeStep(t) == 1, "update at " << t);
    }
    SB_CHECK(source->Executions == 1,
      "the input executed " << source->Executions << " times; the filter's time must not reach it");
    const unsigned long long steps1 = filter->GetSimulatedStepsTotal();
    filter->UpdateTimeStep(0.3);
    SB_CHECK(filter->GetSimulatedStepsTotal() == steps1, "frame 3 comes from the cache");
  }

  // Field data TimeStep is the step taken: the frame interval split into equal steps no larger
  // than the automatic (or given) step, so StepCount x TimeStep lands exactly on each frame.
  {
    auto box = sbtest::MakeTetBox(2, 2, 2, 0.05, { 0.0, 0.0, 0.2 });
    sbtest::CapturedFilter f(box);
    f.Filter->SetFrameInterval(0.04);
    f.Filter->SetEndTime(0.2);
    f.Filter->SetTimeStep(3.0e-4); // 0.04 / 3e-4 = 133.3: 134 steps of 0.04 / 134 per frame
    SB_CHECK(f.Update(0.12), f.Messages->AllErrors());
    const double step = sbtest::FieldValue(f.Mesh(), "TimeStep");
    const double steps = sbtest::FieldValue(f.Mesh(), "StepCount");
    SB_CHECK(std::abs(step - 0.04 / 134.0) < 1e-15, "TimeStep is the step taken, 0.04 / 134 = "
      << 0.04 / 134.0 << ", got " << step << " (the setting is 3e-4)");
    SB_CHECK(steps == 3 * 134, "3 frames of 134 steps, got " << steps);
    f.Filter->SetMethod(vtkSoftBodyFilter::XPBD);
    f.Filter->SetTimeStep(0.0); // automatic: at most 1/120 s, so 5 steps of 0.008 s per frame
    SB_CHECK(f.Update(0.04), f.Messages->AllErrors());
    const double pbdStep = sbtest::FieldValue(f.Mesh(), "TimeStep");
    SB_CHECK(std::abs(pbdStep - 0.008) < 1e-15, "XPBD TimeStep 0.04 / 5 = 0.008, got " << pbdStep);
  }

  return sbtest::Result("filter.time_protocol");
}
