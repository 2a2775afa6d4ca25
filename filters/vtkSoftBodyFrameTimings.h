/**
 * @class   vtkSoftBodyFrameTimings
 * @brief   Where the wall time of a Soft Body run went, frame by frame: the Timings port.
 *
 * The simulation's stages (the Plan: forces, integration, collision detection, ...) keep their
 * accumulated wall time; what each frame cost is the difference across that frame's interval,
 * recorded when the frame is simulated (a frame replayed from the cache keeps its record). The
 * Timings port is a table with a row per simulated frame up to the one shown: its time, each
 * stage's seconds, Other (the frame's wall time outside the stages: the filter, the cache) and
 * Total, so ParaView's Line or Bar Chart View draws one series per stage against Time. Set-up
 * (building the simulation from the input) is not a frame: it goes into field data
 * SetupSeconds, beside SimulationSeconds, the frames' total.
 *
 * Plain C++, private to the filter.
 */
#ifndef vtkSoftBodyFrameTimings_h
#define vtkSoftBodyFrameTimings_h

#include "softbody/common/step_plan.h" // softbody::StageTiming

#include <map>
#include <string>
#include <vector>

class vtkFieldData;
class vtkTable;

class vtkSoftBodyFrameTimings
{
public:
  /// A new simulation, built in `setupSeconds`: no frame recorded.
  void Reset(double setupSeconds);
  /// Forgets the frames after `frame` (they will be simulated again).
  void DropAfter(int frame);
  /// Frame `frame` (ending at `time`) took `wallSeconds`; the stages' totals were `before` at
  /// its start and are `after` now.
  void Record(int frame, double time, const std::vector<softbody::StageTiming>& before,
    const std::vector<softbody::StageTiming>& after, double wallSeconds);

  /// The rows of the frames at or before `time`, into `output` (emptied first).
  void FillTable(double time, vtkTable* output) const;
  /// SetupSeconds and SimulationSeconds (the recorded frames' wall time up to `time`).
  void AddFields(double time, vtkFieldData* field) const;

private:
  struct Frame
  {
    double Time = 0.0;
    std::vector<double> Seconds; ///< per entry of Labels (shorter: the later ones not run), spent in this frame
    double Wall = 0.0;
  };
  double SetupSeconds = 0.0;
  /// The stages' labels, in the order they first ran: the table's columns.
  std::vector<std::string> Labels;
  std::map<int, Frame> Frames;
};

#endif
