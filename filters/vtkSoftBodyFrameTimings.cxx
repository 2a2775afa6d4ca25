#include "vtkSoftBodyFrameTimings.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkTable.h"

#include <algorithm>

namespace
{
/// Frames whose time is at or before `time` (within the frame grid's rounding).
bool AtOrBefore(double frameTime, double time)
{
  return frameTime <= time + 1e-9 * std::max(1.0, std::abs(time));
}

vtkNew<vtkDoubleArray> Scalar(const char* name, double value)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->InsertNextValue(value);
  return array;
}
} // namespace

//------------------------------------------------------------------------------
void vtkSoftBodyFrameTimings::Reset(double setupSeconds)
{
  this->SetupSeconds = setupSeconds;
  this->Labels.clear();
  this->Frames.clear();
}

//------------------------------------------------------------------------------
void vtkSoftBodyFrameTimings::DropAfter(int frame)
{
  this->Frames.erase(this->Frames.upper_bound(frame), this->Frames.end());
}

//------------------------------------------------------------------------------
void vtkSoftBodyFrameTimings::Record(int frame, double time,
  const std::vector<softbody::StageTiming>& before, const std::vector<softbody::StageTiming>& after,
  double wallSeconds)
{
  Frame record;
  record.Time = time;
  record.Wall = wallSeconds;
  for (const softbody::StageTiming& stage : after)
  {
    // A simulation's plan keeps its stages; matched by label all the same, so a stage that
    // first runs later gets a column of its own.
    const auto column = std::find(this->Labels.begin(), this->Labels.end(), stage.label);
    const std::size_t c = static_cast<std::size_t>(column - this->Labels.begin());
    if (column == this->Labels.end())
    {
      this->Labels.push_back(stage.label);
    }
    const auto start = std::find_if(before.begin(), before.end(),
      [&](const softbody::StageTiming& b) { return b.label == stage.label; });
    record.Seconds.resize(std::max(record.Seconds.size(), c + 1), 0.0);
    record.Seconds[c] = stage.seconds - (start == before.end() ? 0.0 : start->seconds);
  }
  this->Frames[frame] = std::move(record);
}

//------------------------------------------------------------------------------
void vtkSoftBodyFrameTimings::FillTable(double time, vtkTable* output) const
{
  output->Initialize();
  vtkNew<vtkDoubleArray> times, other, total;
  times->SetName("Time");
  other->SetName("Other");
  total->SetName("Total");
  std::vector<vtkSmartPointer<vtkDoubleArray>> stages;
  for (const std::string& label : this->Labels)
  {
    stages.push_back(vtkSmartPointer<vtkDoubleArray>::New());
    stages.back()->SetName(label.c_str());
  }
  for (const auto& [frame, record] : this->Frames)
  {
    if (!AtOrBefore(record.Time, time))
    {
      break;
    }
    times->InsertNextValue(record.Time);
    double staged = 0.0;
    for (std::size_t c = 0; c < stages.size(); ++c)
    {
      const double seconds = c < record.Seconds.size() ? record.Seconds[c] : 0.0;
      stages[c]->InsertNextValue(seconds);
      staged += seconds;
    }
    // The stages' timers run inside the frame's and never overlap: the rest is not negative
    // (python.timings checks it for each method, so a stage timed twice shows).
    other->InsertNextValue(record.Wall - staged);
    total->InsertNextValue(record.Wall);
  }
  output->AddColumn(times);
  for (const auto& stage : stages)
  {
    output->AddColumn(stage);
  }
  output->AddColumn(other);
  output->AddColumn(total);
  this->AddFields(time, output->GetFieldData());
}

//------------------------------------------------------------------------------
void vtkSoftBodyFrameTimings::AddFields(double time, vtkFieldData* field) const
{
  double simulated = 0.0;
  for (const auto& [frame, record] : this->Frames)
  {
    if (AtOrBefore(record.Time, time))
    {
      simulated += record.Wall;
    }
  }
  field->AddArray(Scalar("SetupSeconds", this->SetupSeconds));
  field->AddArray(Scalar("SimulationSeconds", simulated));
}
