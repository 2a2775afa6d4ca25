#include "pqSoftBodyKeyframeRecorder.h"

#include <pqAnimationCue.h>
#include <pqAnimationScene.h>
#include <pqApplicationCore.h>
#include <pqPipelineSource.h>
#include <pqServerManagerModel.h>
#include <vtkCommand.h>
#include <vtkEventQtSlotConnect.h>
#include <vtkPVXMLElement.h>
#include <vtkSMAnimationScene.h>
#include <vtkSMProperty.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMPropertyIterator.h>
#include <vtkSMProxy.h>
#include <vtkSMSessionProxyManager.h>
#include <vtkSmartPointer.h>

#include <cmath>
#include <cstring>

namespace
{

constexpr const char* kConditionProxy = "SoftBodyCondition";
constexpr const char* kRecordedHint = "RecordedWhilePlaying";
// vtkPVCompositeKeyFrame's BOOLEAN: a keyframe's value holds until the next one.
constexpr int kBooleanInterpolation = 1;
// Two times (normalized key times, or seconds) closer than this are the same frame.
constexpr double kSameKey = 1e-9;

pqAnimationScene* sceneOf(pqPipelineSource* source)
{
  const QList<pqAnimationScene*> scenes =
    pqApplicationCore::instance()->getServerManagerModel()->findItems<pqAnimationScene*>(source->getServer());
  return scenes.isEmpty() ? nullptr : scenes.front();
}

/// The time the scene stands at, or ticks to while its tracks set their properties (the proxy's
/// AnimationTime still holds the time before during the tick).
double sceneTime(pqAnimationScene* scene)
{
  auto* clock = vtkSMAnimationScene::SafeDownCast(scene->getProxy()->GetClientSideObject());
  return clock ? clock->GetSceneTime() : scene->getAnimationTime();
}

double normalized(pqAnimationScene* scene, double time)
{
  const QPair<double, double> clock = scene->getClockTimeRange();
  const double span = clock.second - clock.first;
  return span > 0.0 ? (time - clock.first) / span : 0.0;
}

double keyTime(vtkSMProxy* keyframe)
{
  return vtkSMPropertyHelper(keyframe, "KeyTime").GetAsDouble();
}

vtkSmartPointer<vtkSMProxy> booleanKeyframe(vtkSMSessionProxyManager* manager, double key, double value)
{
  vtkSmartPointer<vtkSMProxy> keyframe;
  keyframe.TakeReference(manager->NewProxy("animation_keyframes", "CompositeKeyFrame"));
  vtkSMPropertyHelper(keyframe, "Type").Set(kBooleanInterpolation);
  vtkSMPropertyHelper(keyframe, "KeyTime").Set(key);
  vtkSMPropertyHelper(keyframe, "KeyValues").Set(&value, 1);
  keyframe->UpdateVTKObjects();
  return keyframe;
}

void setKeyframes(pqAnimationCue* cue, const std::vector<vtkSmartPointer<vtkSMProxy>>& keyframes)
{
  std::vector<vtkSMProxy*> raw;
  for (const auto& keyframe : keyframes)
  {
    raw.push_back(keyframe);
  }
  vtkSMPropertyHelper(cue->getProxy(), "KeyFrames").Set(raw.data(), static_cast<unsigned int>(raw.size()));
  cue->getProxy()->UpdateVTKObjects();
}

} // namespace

//------------------------------------------------------------------------------
pqSoftBodyKeyframeRecorder::pqSoftBodyKeyframeRecorder(QObject* parent)
  : QObject(parent)
{
}

pqSoftBodyKeyframeRecorder::~pqSoftBodyKeyframeRecorder() = default;

//------------------------------------------------------------------------------
void pqSoftBodyKeyframeRecorder::startup()
{
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  QObject::connect(model, &pqServerManagerModel::sourceAdded, this, &pqSoftBodyKeyframeRecorder::watch);
  QObject::connect(model, &pqServerManagerModel::sourceRemoved, this, &pqSoftBodyKeyframeRecorder::forget);
  for (pqPipelineSource* source : model->findItems<pqPipelineSource*>())
  {
    this->watch(source);
  }
}

void pqSoftBodyKeyframeRecorder::shutdown()
{
  this->Connections->Disconnect();
  this->Conditions.clear();
}

//------------------------------------------------------------------------------
void pqSoftBodyKeyframeRecorder::watch(pqPipelineSource* source)
{
  vtkSMProxy* proxy = source->getProxy();
  if (!proxy || std::strcmp(proxy->GetXMLName(), kConditionProxy) != 0 || this->Conditions.count(proxy))
  {
    return;
  }
  Watched watched;
  watched.source = source;
  vtkSmartPointer<vtkSMPropertyIterator> it;
  it.TakeReference(proxy->NewPropertyIterator());
  for (it->Begin(); !it->IsAtEnd(); it->Next())
  {
    vtkPVXMLElement* hints = it->GetProperty()->GetHints();
    if (hints && hints->FindNestedElementByName(kRecordedHint))
    {
      watched.values[it->GetKey()] = vtkSMPropertyHelper(it->GetProperty()).GetDoubleArray();
    }
  }
  this->Conditions[proxy] = std::move(watched);
  this->Connections->Connect(proxy, vtkCommand::PropertyModifiedEvent, this,
    SLOT(onPropertyModified(vtkObject*, unsigned long, void*, void*)));
}

void pqSoftBodyKeyframeRecorder::forget(pqPipelineSource* source)
{
  vtkSMProxy* proxy = source->getProxy();
  if (this->Conditions.erase(proxy))
  {
    this->Connections->Disconnect(proxy);
  }
}

//------------------------------------------------------------------------------
void pqSoftBodyKeyframeRecorder::onPropertyModified(vtkObject* caller, unsigned long, void*, void* callData)
{
  vtkSMProxy* proxy = vtkSMProxy::SafeDownCast(caller);
  const auto condition = this->Conditions.find(proxy);
  if (condition == this->Conditions.end() || !callData)
  {
    return;
  }
  const auto property = condition->second.values.find(static_cast<const char*>(callData));
  if (property == condition->second.values.end())
  {
    return; // not a value the filter changes live
  }
  const std::vector<double> before = property->second;
  const std::vector<double> now = vtkSMPropertyHelper(proxy, property->first.c_str()).GetDoubleArray();
  property->second = now;

  pqPipelineSource* source = condition->second.source;
  // The panel's first Apply of a new condition sets it up: the filter builds anew, no live change.
  if (source->modifiedState() == pqProxy::UNINITIALIZED || before.size() != now.size())
  {
    return;
  }
  pqAnimationScene* scene = sceneOf(source);
  if (!scene)
  {
    return;
  }
  const double time = sceneTime(scene);
  const std::optional<double> frame = changeFrameTime(source, time);
  if (!frame)
  {
    return; // no Soft Body run takes this condition
  }
  const bool atStart = *frame <= scene->getClockTimeRange().first;
  const double key = normalized(scene, *frame);
  for (std::size_t k = 0; k < now.size(); ++k)
  {
    if (now[k] == before[k])
    {
      continue;
    }
    const int component = static_cast<int>(k);
    pqAnimationCue* cue = scene->getCue(proxy, property->first.c_str(), component);
    if (cue)
    {
      if (trackHolds(cue, normalized(scene, time), now[k]))
      {
        continue; // the track itself set the value as the animation played
      }
    }
    else if (atStart)
    {
      continue; // edited before the run starts: a new setting, not a change during it
    }
    else
    {
      cue = newTrack(scene, proxy, property->first, component, before[k]);
    }
    keepUntil(cue, key, now[k]);
  }
}

//------------------------------------------------------------------------------
std::optional<double> pqSoftBodyKeyframeRecorder::changeFrameTime(pqPipelineSource* source, double time)
{
  std::optional<double> frame;
  for (pqPipelineSource* consumer : source->getAllConsumers())
  {
    vtkSMProxy* proxy = consumer->getProxy();
    vtkSMProperty* steps = proxy->GetProperty("TimestepValues");
    if (!steps)
    {
      continue;
    }
    proxy->UpdatePropertyInformation(steps);
    for (double step : vtkSMPropertyHelper(steps).GetDoubleArray())
    {
      // The filter takes a time between frames as a change from the frame before it.
      if (step <= time * (1.0 + kSameKey) + kSameKey && (!frame || step > *frame))
      {
        frame = step;
      }
    }
  }
  return frame;
}

bool pqSoftBodyKeyframeRecorder::trackHolds(pqAnimationCue* cue, double key, double value)
{
  if (vtkSMPropertyHelper(cue->getProxy(), "Enabled").GetAsInt() == 0)
  {
    return false;
  }
  const QList<vtkSMProxy*> keyframes = cue->getKeyFrames();
  vtkSMProxy* last = nullptr;
  for (vtkSMProxy* keyframe : keyframes)
  {
    if (keyTime(keyframe) <= key + kSameKey)
    {
      last = keyframe;
    }
  }
  if (!last)
  {
    return false;
  }
  const bool holds = vtkSMPropertyHelper(last, "Type").GetAsInt() == kBooleanInterpolation ||
    last == keyframes.back() || std::abs(keyTime(last) - key) <= kSameKey;
  // A track the user made interpolating owns the property between its keyframes.
  return !holds || vtkSMPropertyHelper(last, "KeyValues").GetAsDouble() == value;
}

void pqSoftBodyKeyframeRecorder::keepUntil(pqAnimationCue* cue, double key, double value)
{
  std::vector<vtkSmartPointer<vtkSMProxy>> kept;
  for (vtkSMProxy* keyframe : cue->getKeyFrames())
  {
    if (keyTime(keyframe) < key - kSameKey)
    {
      kept.emplace_back(keyframe);
    }
  }
  kept.push_back(booleanKeyframe(cue->getProxy()->GetSessionProxyManager(), key, value));
  setKeyframes(cue, kept);
}

pqAnimationCue* pqSoftBodyKeyframeRecorder::newTrack(
  pqAnimationScene* scene, vtkSMProxy* proxy, const std::string& property, int component, double before)
{
  pqAnimationCue* cue = scene->createCue(proxy, property.c_str(), component);
  setKeyframes(cue, { booleanKeyframe(proxy->GetSessionProxyManager(), 0.0, before) });
  return cue;
}
