// The GUI's recorder of live condition changes: while the animation stands at or plays through
// a frame of a Soft Body run, a Soft Body Condition whose values change (a Pull handle dragged,
// a Force typed, then applied) gets keyframes, so that the run can be played again, scripted and
// saved in a state file.
//
// The Soft Body filter applies such a change from the frame shown on and keeps the frames
// before (vtkSoftBodyFrameRunner); this class writes the same history as animation tracks, the
// way softbody.keyframes.record does from the filter's field data in pvpython: one track per
// property component that changed, a Boolean keyframe at the start holding the value before
// and one at the change's frame holding the new value. A change at a frame before the last
// keyframe drops the keyframes after it, as the filter drops the frames after it.
//
// Only the properties the filter can change live are recorded; the XML marks them with the hint
// <RecordedWhilePlaying/>. Values the tracks themselves write while the animation plays are
// recognized (they equal what the track holds at that time) and not recorded again.
#ifndef pqSoftBodyKeyframeRecorder_h
#define pqSoftBodyKeyframeRecorder_h

#include <QObject>

#include <vtkNew.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

class pqAnimationCue;
class pqAnimationScene;
class pqPipelineSource;
class vtkEventQtSlotConnect;
class vtkObject;
class vtkSMProxy;

class pqSoftBodyKeyframeRecorder : public QObject
{
  Q_OBJECT

public:
  explicit pqSoftBodyKeyframeRecorder(QObject* parent = nullptr);
  ~pqSoftBodyKeyframeRecorder() override;

  // pqAutoStartInterface, called by the plugin's generated implementation.
  void startup();
  void shutdown();

private Q_SLOTS:
  void watch(pqPipelineSource* source);
  void forget(pqPipelineSource* source);
  void onPropertyModified(vtkObject* caller, unsigned long event, void* clientData, void* callData);

private:
  /// A watched condition: the values of its recorded properties as last seen.
  struct Watched
  {
    pqPipelineSource* source = nullptr;
    std::map<std::string, std::vector<double>> values;
  };

  /// The frame the Soft Body filters fed by `source` apply a change at when the scene stands at
  /// `time`: the latest of their time steps at or before it; none when no consumer has steps.
  static std::optional<double> changeFrameTime(pqPipelineSource* source, double time);
  /// Whether `value` is what the track holds at normalized time `key` (its own write).
  static bool trackHolds(pqAnimationCue* cue, double key, double value);
  /// The track's keyframes before `key`, then a Boolean keyframe at `key` holding `value`.
  static void keepUntil(pqAnimationCue* cue, double key, double value);
  /// A new track whose keyframe at the start holds `before`.
  static pqAnimationCue* newTrack(
    pqAnimationScene* scene, vtkSMProxy* proxy, const std::string& property, int component, double before);

  std::map<vtkSMProxy*, Watched> Conditions;
  vtkNew<vtkEventQtSlotConnect> Connections;
};

#endif
