"""Changes made to Soft Body Conditions during playback, as animation keyframes.

    from softbody import keyframes
    tracks = keyframes.record(body, [hand])   # after moving the hand's widget while playing

When a condition's values change while the animation plays (a Pull handle dragged, a Force
typed), the Soft Body filter keeps the frames up to the one shown and applies the change from
there on; its Mesh output's field data lists when (`ConditionChangeTimes`) and what each
condition held from frame 0 and after each change (`ConditionValues NAME PROPERTY`). `record`
turns that into keyframes of the conditions' properties: one animation track per property and
component whose value changed, a keyframe at 0 s and at each change holding the value until the
next (ParaView's Boolean interpolation). Played again (the animation's Play, or setting its
AnimationTime frame by frame in pvpython), the properties change at the same frames and the run
is the same run; saved in a state file, the keyframes open with it, and they are ordinary
animation tracks to edit or script.

The conditions are matched to the field data by their ConditionName; a condition that never
changed gets no track. Returns the tracks it made or filled (a track already there for the same
property and component is overwritten).
"""

from paraview import servermanager
from paraview.simple import CompositeKeyFrame, GetAnimationScene, GetAnimationTrack


def _field_data(body):
    """The field data of the Soft Body filter's Mesh output at the scene's end."""
    scene = GetAnimationScene()
    body.UpdatePipeline(scene.EndTime)
    mesh = servermanager.Fetch(body, 0)
    return mesh.GetFieldData()


def _normalized(time, scene):
    span = scene.EndTime - scene.StartTime
    return (time - scene.StartTime) / span if span > 0 else 0.0


def record(body, conditions):
    """Keyframes of the `conditions` (Soft Body Condition proxies) from the changes the Soft Body
    filter `body` recorded while playing; returns the animation tracks made."""
    field = _field_data(body)
    changes = field.GetArray("ConditionChangeTimes")
    if changes is None:
        return []
    times = [0.0] + [changes.GetValue(i) for i in range(changes.GetNumberOfTuples())]
    scene = GetAnimationScene()
    tracks = []
    for condition in conditions:
        name = condition.ConditionName
        prefix = f"ConditionValues {name} "
        for a in range(field.GetNumberOfArrays()):
            array = field.GetArray(a)
            if array is None or not array.GetName().startswith(prefix):
                continue
            if array.GetNumberOfTuples() != len(times):
                raise ValueError(f"ConditionValues for '{name}' have {array.GetNumberOfTuples()} entries "
                                 f"for {len(times)} times: not from one run")
            prop = array.GetName()[len(prefix):]
            components = array.GetNumberOfComponents()
            for k in range(components):
                values = [array.GetComponent(i, k) for i in range(len(times))]
                if all(v == values[0] for v in values):
                    continue
                track = GetAnimationTrack(prop, index=k if components > 1 else None, proxy=condition)
                frames = []
                for time, value in zip(times, values):
                    frame = CompositeKeyFrame()
                    frame.Interpolation = "Boolean"
                    frame.KeyTime = _normalized(time, scene)
                    frame.KeyValues = [value]
                    frames.append(frame)
                track.KeyFrames = frames
                tracks.append(track)
    return tracks
