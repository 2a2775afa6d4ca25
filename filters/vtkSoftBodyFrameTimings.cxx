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
    // The plan's stages are the same across a frame; matched by label all the same.
    const auto start = std::find_if(before.begin(), before.end(),
      [&](const softbody::StageTiming& b) { return b.label == stage.label; });
    record.Labels.push_back(stage.label);
    record.Seconds.push_back(stage.seconds - (start == before.end() ? 0.0 : start->seconds));
  }
  this->Frames[frame] = std::move(record);
}

//------------------------------------------------------------------------------
void vtkSoftBodyFrameTimings::FillTable(double time, vtkTable* output) const
{
  output->Initialize();
  // The columns: every stage any shown frame ran, in the order they first appear.
  std::vector<std::string> labels;
  for (const auto& [frame, record] : this->Frames)
  {
    if (!AtOrBefore(record.Time, time))
    {
      break;
    }
    for (const std::string& label : record.Labels)
    {
      if (std::find(labels.begin(), labels.end(), label) == labels.end())
      {
        labels.push_back(label);
      }
    }
  }
  vtkNew<vtkDoubleArray> times;
  times->SetName("Time");
  std::vector<vtkSmartPointer<vtkDoubleArray>> stages;
  for (const std::string& label : labels)
  {
    stages.push_back(vtkSmartPointer<vtkDoubleArray>::New());
    stages.back()->SetName(label.c_str());
  }
  vtkNew<vtkDoubleArray> other, total;
  other->SetName("Other");
  total->SetName("Total");
  for (const auto& [frame, record] : this->Frames)
  {
    if (!AtOrBefore(record.Time, time))
    {
      break;
    }
    times->InsertNextValue(record.Time);
    double staged = 0.0;
    for (std::size_t c = 0; c < labels.size(); ++c)
    {
      const auto at = std::find(record.Labels.begin(), record.Labels.end(), labels[c]);
      const double seconds = at == record.Labels.end() ? 0.0 : record.Seconds[at - record.Labels.begin()];
      stages[c]->InsertNextValue(seconds);
      staged += seconds;
    }
    other->InsertNextValue(std::max(0.0, record.Wall - staged));
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
