"""GUI smoke test, run inside the real ParaView GUI by run_gui.sh (see gui_support.py).

Loads the plugin, opens data/jelly.vtu, applies Soft Body as the Apply button does, and checks
what a new user sees: only the Mesh and the Floor shown, in the one render view (no spreadsheet
or chart pane for Convergence, no particles over the mesh), the Mesh coloured by Velocity, the
render view still the active view, the animation stepping through the filter's times, and no
error or warning in the Output Messages window. A Pull condition on the jelly, made active so
its panel builds its widgets, changed while the animation stands at a frame, is applied from
that frame on and recorded as keyframes by the GUI itself; played again from the start, the
keyframes repeat the change at the same frame and the same Mesh; softbody.keyframes fills the
same tracks; a
change between two frames is keyed at the frame the filter applies it from. Then the same Apply on a
voxelized torus (with the torus as its Surface) and on the cloth, both under XPBD: the same two ports, still one view,
both bodies following the animation time.
"""
import os
import sys

sys.path.insert(0, os.environ["SOFTBODY_GUI_DIR"])
import gui_support  # noqa: E402



def hand_tracks(scene, condition):
    """{(property, component): [(key time, value), ...]} of the scene's tracks of `condition`."""
    tracks = {}
    for cue in scene.Cues:
        animated = cue.GetProperty("AnimatedProxy") and cue.AnimatedProxy
        if animated is not None and animated.SMProxy is condition.SMProxy:
            frames = [(f.KeyTime, f.KeyValues[0]) for f in cue.KeyFrames if f.Interpolation == "Boolean"]
            tracks[(cue.AnimatedPropertyName, cue.AnimatedElement)] = frames
    return tracks


def mesh_points(body):
    """The Mesh output's points at the scene's time, as a list (compared exactly)."""
    from paraview import servermanager
    points = servermanager.Fetch(body).GetPoints()
    return [points.GetPoint(i) for i in range(points.GetNumberOfPoints())]


def frame_timings(body):
    """(time, wall seconds) of each simulated frame, from the Timings output."""
    from paraview import servermanager
    table = servermanager.Fetch(body, idx=5)
    time, total = table.GetColumnByName("Time"), table.GetColumnByName("Total")
    return [(time.GetValue(r), total.GetValue(r)) for r in range(table.GetNumberOfRows())]


failures = []
try:
    messages = gui_support.OutputMessages()
    from paraview.simple import (GetActiveView, GetAnimationScene, GetDisplayProperties,
                                 GetViews, OutputPort, Render, SetActiveSource,
                                 XMLPolyDataReader, XMLUnstructuredGridReader)
    gui_support.load_plugin(globals())

    reader = XMLUnstructuredGridReader(FileName=[gui_support.data_file("jelly.vtu")])
    gui_support.apply_like_gui(reader)
    body = SoftBody(Input=reader, EndTime=1.0)
    shown = gui_support.apply_like_gui(body)

    expected = {0: "RenderView", 1: None, 2: None, 3: None, 4: "RenderView", 5: None}
    if shown != expected:
        failures.append("Apply showed ports %s, expected %s" % (shown, expected))
    views = [view.GetXMLName() for view in GetViews()]
    if views != ["RenderView"]:
        failures.append("views after Apply: %s, expected one RenderView" % views)
    view = GetActiveView()
    if view is None or view.GetXMLName() != "RenderView":
        failures.append("the active view is %s, not the render view"
                        % (view.GetXMLName() if view else None))
    if gui_support.visible_ports(reader, view):
        failures.append("the input stays visible under the body")
    colour = GetDisplayProperties(OutputPort(body, 0), view).ColorArrayName
    if list(colour) != ["POINTS", "Velocity"]:
        failures.append("Mesh coloured by %s, expected POINTS Velocity" % list(colour))

    # Step the animation as the VCR toolbar's Next Frame does.
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    times = list(body.TimestepValues)
    for _ in range(5):
        scene.GoToNext()
        Render(view)
    if abs(scene.AnimationTime - times[5]) > 1e-9:
        failures.append("after 5 Next Frame the time is %g, expected %g"
                        % (scene.AnimationTime, times[5]))
    simulated = body.GetFieldDataInformation().GetArray("SimulationTime").GetRange(0)[0]
    if abs(simulated - times[5]) > 1e-9:
        failures.append("the Mesh is at SimulationTime %g, expected %g" % (simulated, times[5]))
    floor_bounds = OutputPort(body, 4).GetDataInformation().GetBounds()
    if not (floor_bounds[4] == floor_bounds[5] == 0.0 and floor_bounds[1] > floor_bounds[0]):
        failures.append("the Floor port is not a square in the plane z = 0: %s"
                        % (floor_bounds,))
    if GetActiveView().GetXMLName() != "RenderView":
        failures.append("after stepping, the active view is %s" % GetActiveView().GetXMLName())

    # A Pull condition on the jelly, applied and made active as a user does (its panel builds
    # the sphere and handle widgets), pulled while the animation stands at a frame: the
    # change applies from that frame on (ConditionChangeTimes), the frames before stay.
    hand = SoftBodyCondition(Input=reader, ConditionName="hand", ConditionType="Pull",
                             Region="Sphere", SphereCenter=[0.15, 0, 0.5], SphereRadius=0.04,
                             PullTarget=[0.3, 0, 0.6], PullStiffness=50)
    gui_support.apply_like_gui(hand)
    if hand.GetDataInformation().GetNumberOfPoints() == 0:
        failures.append("the Pull condition's sphere selects no point of the jelly")
    held = SoftBody(Input=reader, Conditions=[hand], EndTime=1.0)
    gui_support.apply_like_gui(held)
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = times[3]
    Render(view)
    rest = mesh_points(reader)
    pulled = [i for i, p in enumerate(rest) if sum((a - b) ** 2 for a, b in zip(p, [0.15, 0, 0.5])) <= 0.04 ** 2]
    y_at_change = sum(mesh_points(held)[i][1] for i in pulled) / len(pulled)
    SetActiveSource(hand)
    hand.PullTarget = [0.0, 0.3, 0.7]  # what dragging the handle writes
    Render(view)
    scene.AnimationTime = times[5]
    Render(view)
    y_after = sum(mesh_points(held)[i][1] for i in pulled) / len(pulled)
    if not y_after > y_at_change + 1e-4:
        failures.append("the pull moved towards y = 0.3 at t = %g: its points went from y = %g to %g by t = %g"
                        % (times[3], y_at_change, y_after, times[5]))
    changes = held.GetFieldDataInformation().GetArray("ConditionChangeTimes")
    if changes is None or abs(changes.GetRange(0)[0] - times[3]) > 1e-9:
        failures.append("the pull moved at t = %g is not recorded from there (ConditionChangeTimes %s)"
                        % (times[3], changes.GetRange(0) if changes else None))
    # The GUI recorded the change as keyframes by itself (plugin/gui): a track per PullTarget
    # component moved, a Boolean keyframe at the start holding the old target and one at the
    # change's frame holding the new one.
    live_points = mesh_points(held)  # at times[5]
    live_timings = frame_timings(held)
    before, after = [0.3, 0.0, 0.6], [0.0, 0.3, 0.7]
    key = (times[3] - scene.StartTime) / (scene.EndTime - scene.StartTime)
    expected_tracks = {("PullTarget", k): [(0.0, before[k]), (key, after[k])] for k in range(3)}
    if hand_tracks(scene, hand) != expected_tracks:
        failures.append("the pull moved at t = %g was recorded as %s, expected %s"
                        % (times[3], hand_tracks(scene, hand), expected_tracks))
    # Played again from the start, frame by frame: the tracks set the target back and move it at
    # the same frame, the tracks' own changes add no keyframe, and the filter, finding the values
    # in force at each frame, keeps every simulated frame (the same wall times: none ran again).
    scene.AnimationTime = times[0]
    Render(view)
    if list(hand.PullTarget) != before:
        failures.append("at t = 0 the tracks set PullTarget %s, expected %s" % (list(hand.PullTarget), before))
    for _ in range(5):
        scene.GoToNext()
        Render(view)
    if list(hand.PullTarget) != after:
        failures.append("at t = %g the tracks set PullTarget %s, expected %s"
                        % (times[5], list(hand.PullTarget), after))
    if mesh_points(held) != live_points:
        failures.append("at t = %g the replayed Mesh differs from the live run's" % times[5])
    if frame_timings(held) != live_timings or len(live_timings) < 5:
        failures.append("the replay simulated frames again: Timings %s, live %s" % (frame_timings(held), live_timings))
    changes = held.GetFieldDataInformation().GetArray("ConditionChangeTimes")
    if changes is None or changes.GetNumberOfTuples() != 1 or abs(changes.GetRange(0)[0] - times[3]) > 1e-9:
        failures.append("the replay changed the pull at %s, expected once at t = %g"
                        % (changes.GetRange(0) if changes else None, times[3]))
    if hand_tracks(scene, hand) != expected_tracks:
        failures.append("the replay changed the recorded keyframes to %r from %r" % (hand_tracks(scene, hand), expected_tracks))
    # The same from the field data through softbody.keyframes (pvpython's way): it fills the
    # tracks already there.
    from softbody import keyframes
    tracks = keyframes.record(held, [hand])
    moved = sorted((t.AnimatedPropertyName, t.AnimatedElement) for t in tracks)
    if moved != [("PullTarget", 0), ("PullTarget", 1), ("PullTarget", 2)]:
        failures.append("keyframes.record made tracks %s, expected PullTarget's three components" % moved)
    if sorted(hand_tracks(scene, hand)) != sorted(expected_tracks):
        failures.append("after keyframes.record the pull has tracks %s" % sorted(hand_tracks(scene, hand)))
    # A change while the scene stands between two frames: the filter applies it from the frame
    # before, and the keyframe is there.
    scene.AnimationTime = times[4] + 0.4 * (times[5] - times[4])
    Render(view)
    hand.PullStiffness = 30
    Render(view)
    changes = held.GetFieldDataInformation().GetArray("ConditionChangeTimes")
    stiffness = hand_tracks(scene, hand).get(("PullStiffness", 0))
    key4 = (times[4] - scene.StartTime) / (scene.EndTime - scene.StartTime)
    if changes is None or abs(changes.GetRange(0)[1] - times[4]) > 1e-9 or stiffness != [(0.0, 50.0), (key4, 30.0)]:
        failures.append("a stiffness changed between frames %g and %g: the filter took it at %s, the keyframes %s"
                        % (times[4], times[5], changes.GetRange(0) if changes else None, stiffness))

    # The two particle bodies, under XPBD: a voxelized surface given as its own
    # Surface, and the cloth. Apply shows the same two ports and opens no pane for either.
    torus = XMLPolyDataReader(FileName=[gui_support.data_file("torus.vtp")])
    gui_support.apply_like_gui(torus)
    lattice = SoftBodyVoxelize(Input=torus, Resolution=12)
    gui_support.apply_like_gui(lattice)
    voxel_body = SoftBody(Input=lattice, Surface=torus, Method="XPBD", EndTime=0.4)
    cloth = SoftBodyCloth(Resolution=[12, 12])
    gui_support.apply_like_gui(cloth)
    cloth_body = SoftBody(Input=cloth, Method="XPBD", PinnedPointsArray="Pinned", EndTime=0.4)
    for name, source in (("voxelized torus", voxel_body), ("cloth", cloth_body)):
        shown = gui_support.apply_like_gui(source)
        if shown != expected:
            failures.append("%s: Apply showed ports %s, expected %s" % (name, shown, expected))
    views = [view.GetXMLName() for view in GetViews()]
    if views != ["RenderView"]:
        failures.append("views after the particle bodies: %s, expected one RenderView" % views)
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = 0.2
    Render(view)
    for name, source in (("voxelized torus", voxel_body), ("cloth", cloth_body)):
        time = source.GetFieldDataInformation().GetArray("SimulationTime").GetRange(0)[0]
        if abs(time - 0.2) > 1e-9:
            failures.append("%s: at SimulationTime %g, expected 0.2" % (name, time))
    gui_support.finish_later(failures, messages, shot=os.environ.get("SOFTBODY_GUI_SHOT"))
except Exception:
    gui_support.fail_now(failures)
