"""python.load_and_times: the plugin loads as a user loads it, and the Soft Body filter
advertises the frame times EndTime / FrameInterval ask for (TimestepValues, TimeRange and the
animation scene)."""

import os

from paraview.simple import *  # noqa: F401,F403 (the pvpython API, as users write it)

import softbody_testing as sbt

args = sbt.parse_args(__doc__)

# LoadPlugin adds the plugin's proxies as functions to the namespace given as ns; without
# ns=globals() they would land in paraview.simple only.
LoadPlugin(args.plugin, remote=False, ns=globals())
sbt.check("SoftBody" in globals(), "LoadPlugin(ns=globals()) defines SoftBody()")

mesh = os.path.join(args.data_dir, "jelly.vtu")
reader = XMLUnstructuredGridReader(registrationName="jelly.vtu", FileName=[mesh])
body = SoftBody(registrationName="SoftBody", Input=reader)

# Defaults of the public API.
sbt.check(body.GetXMLLabel() == "Soft Body", f"label is 'Soft Body' ({body.GetXMLLabel()!r})")
sbt.check(body.Method == "Automatic", f"Method default Automatic ({body.Method})")
sbt.check(body.Integrator == "Euler-Cromer", f"Integrator default Euler-Cromer ({body.Integrator})")
sbt.check(body.MaterialMode == "Physical", f"MaterialMode default Physical ({body.MaterialMode})")
sbt.check(body.InvertedTets == "Re-orient", f"InvertedTets default Re-orient ({body.InvertedTets})")
sbt.check(body.EndTime == 3.0 and body.FrameInterval == 0.04 and body.TimeStep == 0.0,
          f"EndTime 3, FrameInterval 0.04, TimeStep 0 ({body.EndTime}, {body.FrameInterval}, "
          f"{body.TimeStep})")
sbt.check(list(body.Gravity) == [0.0, 0.0, -9.81], f"Gravity default ({list(body.Gravity)})")
sbt.check(body.Floor == 1 and list(body.FloorNormal) == [0.0, 0.0, 1.0],
          "Floor on, normal +z by default")
sbt.check(body.PinnedPointsArray in ("None", "", None),
          f"PinnedPointsArray pins nothing by default ({body.PinnedPointsArray!r})")
sbt.check(list(body.ListProperties()).count("YoungsModulus") == 1, "YoungsModulus is a property")


def check_times(end_time, frame_interval, expected):
    body.EndTime = end_time
    body.FrameInterval = frame_interval
    # Information-only properties are refreshed by UpdatePipelineInformation, not by the setters.
    body.UpdatePipelineInformation()
    times = list(body.TimestepValues)
    label = f"EndTime {end_time}, FrameInterval {frame_interval}"
    sbt.check(len(times) == len(expected),
              f"{label}: {len(expected)} TimestepValues (got {len(times)})")
    sbt.check(all(abs(a - b) <= 1e-9 * max(1.0, abs(b)) for a, b in zip(times, expected)),
              f"{label}: TimestepValues are {expected[:3]} ... {expected[-2:]} "
              f"(got {times[:3]} ... {times[-2:]})")
    sbt.check(times[-1] == end_time, f"{label}: the last time is EndTime exactly ({times[-1]!r})")
    time_range = list(body.GetPropertyValue("TimeRange"))
    sbt.check(time_range == [0.0, end_time], f"{label}: TimeRange [0, {end_time}] ({time_range})")
    return times


# The defaults: 0, 0.04, ..., 3.0 (76 frames).
check_times(3.0, 0.04, [k * 0.04 for k in range(76)])
# A coarser grid.
check_times(1.0, 0.1, [k * 0.1 for k in range(11)])
# EndTime off the grid: the grid frames, then EndTime itself.
check_times(1.05, 0.1, [k * 0.1 for k in range(11)] + [1.05])
times = check_times(2.0, 0.05, [k * 0.05 for k in range(41)])

# The animation scene sees the same steps (that is what the GUI's VCR controls use).
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
keeper = GetTimeKeeper()
scene_times = list(keeper.TimestepValues)
sbt.check(len(scene_times) == len(times) and
          all(abs(a - b) <= 1e-12 for a, b in zip(scene_times, times)),
          f"the time keeper lists the filter's {len(times)} steps (got {len(scene_times)})")

# Both output ports answer a time request with the frame's time.
for port, name in ((sbt.MESH_PORT, "Mesh"), (sbt.PARTICLES_PORT, "Particles")):
    out = sbt.output_at(body, 0.5, port)
    sbt.check(out is not None and out.GetNumberOfPoints() > 0,
              f"port {port} ({name}) has points at t = 0.5")
    sbt.check(abs(out.GetInformation().Get(out.DATA_TIME_STEP()) - 0.5) < 1e-12,
              f"port {port} ({name}) DATA_TIME_STEP is 0.5")
mesh_out = sbt.output_at(body, 0.5)
sim_time = sbt.field_value(mesh_out, "SimulationTime")
sbt.check(sim_time is not None and abs(sim_time - 0.5) < 1e-9,
          f"field data SimulationTime is 0.5 ({sim_time})")
# Labels read well: acronyms and the possessive survive (ParaView would generate "X PBDLink
# Compliance" and "Youngs Modulus" from the names), and the pvpython names stay the XML names.
quality = SoftBodyMeshQuality(Input=reader)
for proxy in (body, quality):
    for name in proxy.ListProperties():
        label = proxy.GetProperty(name).GetXMLLabel()
        sbt.check(not label.startswith(("X PBD", "P BD")) and "Youngs" not in label,
                  f"{proxy.GetXMLLabel()}.{name} has a readable label ({label!r})")
sbt.check(body.GetProperty("XPBDLinkCompliance").GetXMLLabel() == "XPBD Link Compliance" and
          quality.GetProperty("YoungsModulus").GetXMLLabel() == "Young's Modulus",
          "XPBD Link Compliance and Young's Modulus are labelled as written")
print("python.load_and_times passed")
