"""python.keyframes: changes made to a Soft Body Condition while the animation plays become
animation keyframes that replay the same run (softbody.keyframes), as a GUI user's drag of a Pull
handle would be recorded, replayed and saved.

1. The bundled jelly pulled by a Pull condition, played frame by frame through the animation
   scene; while 0.5 s is shown the handle moves (PullTarget), while 0.8 s is shown the spring
   stiffens (PullStiffness). The Mesh output's field data holds each condition's values from
   frame 0 and after each change (ConditionValues hand PullTarget, ...).
2. keyframes.record makes one track per property component that changed (PullTarget x, y, z and
   PullStiffness), with a keyframe at 0 s and at each change, and a saved state file holds them.
3. The condition put back to its first values and a new Soft Body played through the same
   animation scene: the tracks change the condition at the same frames, and every frame equals
   the live run's bit for bit.
4. Without a change, record makes no track.
5. The properties the XML marks RecordedWhilePlaying (what the GUI's recorder keys,
   plugin/gui) are exactly those the filter records in ConditionValues."""

import os
import tempfile

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())
from softbody import keyframes  # noqa: E402  (the plugin puts the package on the path)

jelly = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
START = {"PullTarget": [0.3, 0.0, 0.6], "PullStiffness": 50.0}
hand = SoftBodyCondition(Input=jelly, ConditionName="hand", ConditionType="Pull", Region="Sphere",
                         SphereCenter=[0.15, 0, 0.5], SphereRadius=0.04, **START)
FRAMES = [round(0.1 * k, 10) for k in range(11)]


def play(body, changes=None):
    """Plays the animation scene over FRAMES, making `changes[t]` (property: value) while t is
    shown; the Mesh output's points per frame."""
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    points = {}
    for t in FRAMES:
        scene.AnimationTime = t
        points[t] = sbt.points_of(sbt.output_at(body, t))
        for prop, value in (changes or {}).get(t, {}).items():
            setattr(hand, prop, value)
            points[t] = sbt.points_of(sbt.output_at(body, t))
    return points


live = SoftBody(Input=jelly, Conditions=[hand], EndTime=1.0, FrameInterval=0.1, TimeStep=0.0)
sbt.check(keyframes.record(live, [hand]) == [], "no change made: no track")
live_points = play(live, {0.5: {"PullTarget": [0.0, 0.3, 0.7]}, 0.8: {"PullStiffness": 80.0}})
field = sbt.output_at(live, 1.0).GetFieldData()
target = field.GetArray("ConditionValues hand PullTarget")
sbt.check(target is not None and target.GetNumberOfTuples() == 3 and target.GetNumberOfComponents() == 3,
          "field data: the hand's PullTarget from frame 0 and after each of the two changes")
sbt.check(np.allclose([target.GetTuple3(i) for i in range(3)], [[0.3, 0, 0.6], [0.0, 0.3, 0.7], [0.0, 0.3, 0.7]]),
          "field data: the PullTarget values in order")
recorded_by_filter = sorted(field.GetArrayName(a)[len("ConditionValues hand "):] for a in range(field.GetNumberOfArrays())
                            if field.GetArrayName(a).startswith("ConditionValues hand "))
hinted = sorted(name for name in hand.ListProperties()
                if (hints := hand.GetProperty(name).SMProperty.GetHints()) is not None
                and hints.FindNestedElementByName("RecordedWhilePlaying") is not None)
print("live values in the field data:", recorded_by_filter, "; marked in the XML:", hinted)
sbt.check(recorded_by_filter == hinted and len(hinted) > 0,
          "the XML marks RecordedWhilePlaying exactly the values the filter changes live")

tracks = keyframes.record(live, [hand])
print("tracks:", [(t.AnimatedPropertyName, t.AnimatedElement, [(k.KeyTime, list(k.KeyValues)) for k in t.KeyFrames])
                  for t in tracks])
sbt.check(len(tracks) == 4, f"one track per changed component: PullTarget x, y, z and PullStiffness (got {len(tracks)})")
stiffness = [t for t in tracks if t.AnimatedPropertyName == "PullStiffness"]
sbt.check(len(stiffness) == 1 and [list(k.KeyValues) for k in stiffness[0].KeyFrames] == [[50.0], [50.0], [80.0]]
          and np.allclose([k.KeyTime for k in stiffness[0].KeyFrames], [0.0, 0.5, 0.8]),
          "PullStiffness keyframes: 50 N/m at 0 s and 0.5 s, 80 N/m at 0.8 s")
state = os.path.join(tempfile.mkdtemp(prefix="softbody_keyframes_"), "pulled.pvsm")
SaveState(state)
with open(state) as saved:
    text = saved.read()
sbt.check('value="PullStiffness"' in text and 'value="PullTarget"' in text,
          "the tracks are in a saved state file")
Delete(live)

for prop, value in START.items():
    setattr(hand, prop, value)
replay = SoftBody(Input=jelly, Conditions=[hand], EndTime=1.0, FrameInterval=0.1, TimeStep=0.0)
replay_points = play(replay)
worst = max(float(np.abs(replay_points[t] - live_points[t]).max()) for t in FRAMES)
print(f"replay: largest difference from the live run over the frames {worst:.1e} m")
sbt.check(all(np.array_equal(replay_points[t], live_points[t]) for t in FRAMES),
          "replayed through the keyframes, every frame equals the live run's")
sbt.check(list(hand.PullTarget) == [0.0, 0.3, 0.7] and hand.PullStiffness == 80.0,
          "the tracks left the condition at its last values")
print("python.keyframes: all checks passed")
