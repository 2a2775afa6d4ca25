"""python.floor_placement: FloorPlacement puts the floor where a user's mesh needs it.

The jelly (data/jelly.vtu, bottom 0.3 m above z = 0) is moved as a scanner would leave it:
- 1.5 m down, below the default floor through (0 0 0). Automatic places the floor through its
  lowest point instead of lifting it 1.2 m, warns quoting FloorOrigin and where the floor went,
  and the body starts where the data put it (up to the contact margin every resting body keeps)
  and rests on that floor, under Mass-Spring and XPBD. Through Floor Origin keeps the old behaviour: lifted onto z = 0.
- at its own place, above the floor: Automatic keeps FloorOrigin (it falls 0.3 m onto z = 0);
  Under the Body puts the floor at its bottom, so it does not fall.
- 100 km away on a tilted floor (FloorNormal 0 1 1, not of unit length): the floor passes
  through the lowest point along the unit normal, to rounding at that distance.
Field data FloorOrigin and the Floor port hold where the floor went; a FloorPlacement out of
range is refused quoting the value.
"""
import os

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())
jelly = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])


def moved(translate):
    transform = Transform(Input=jelly)
    transform.Transform.Translate = list(translate)
    return transform


def warnings_of(frame):
    array = frame.GetFieldData().GetAbstractArray("Warnings")
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())] if array else []


def floor_origin(frame):
    return np.array(frame.GetFieldData().GetArray("FloorOrigin").GetTuple3(0))


# A mesh below the default floor, as scanner coordinates leave it.
below = moved([0.0, 0.0, -1.5])
below.UpdatePipeline()
rest = sbt.points_of(below.GetClientSideObject().GetOutputDataObject(0))
lowest = rest[:, 2].min()
for method in ("Mass-Spring", "XPBD"):
    body = SoftBody(Input=below, Method=method, EndTime=0.5)
    start = sbt.output_at(body, 0.0)
    texts = warnings_of(start)
    print(f"{method}, Automatic, body below the floor: {texts}")
    sbt.check(any("placed under the body" in t and "FloorOrigin (0, 0, 0)" in t for t in texts),
              f"{method}: a warning says the floor was placed under the body, quoting FloorOrigin")
    sbt.check(not any("start below the floor" in t for t in texts), f"{method}: nothing was lifted")
    origin = floor_origin(start)
    sbt.check(origin[0] == 0.0 and origin[1] == 0.0 and lowest - 1e-12 < origin[2] <= lowest,
              f"{method}: field data FloorOrigin {origin} is through the lowest point z = {lowest}")
    # Where the data put it, up to the collision margin every body resting on a floor keeps
    # (a tenth of the mean surface edge; the particle radius plus that for XPBD's lattice-free
    # tet body): a rigid shift along the normal of at most a centimetre, not the 1.2 m lift.
    shift = sbt.points_of(start) - rest
    print(f"{method}: moved at t = 0 by {shift[:, 2].min():.5f} to {shift[:, 2].max():.5f} m along z")
    sbt.check(np.all(shift[:, :2] == 0.0) and np.ptp(shift[:, 2]) < 1e-12 and 0.0 <= shift[0, 2] < 0.01,
              f"{method}: the body starts where the data put it, on the floor's contact margin")
    floor = sbt.points_of(sbt.output_at(body, 0.0, 4))
    sbt.check(np.all(floor[:, 2] == origin[2]), f"{method}: the Floor port is drawn there")
    end = sbt.points_of(sbt.output_at(body, 0.5))
    print(f"{method}: lowest z at 0.5 s {end[:, 2].min():.5f} m, floor at {lowest:.5f} m")
    sbt.check(lowest - 1e-9 <= end[:, 2].min() <= lowest + 0.02, f"{method}: it rests on that floor")
    Delete(body)

lifted = SoftBody(Input=below, FloorPlacement="Through Floor Origin", EndTime=0.5)
start = sbt.output_at(lifted, 0.0)
print(f"Through Floor Origin: lowest z at t = 0 {sbt.points_of(start)[:, 2].min():.5f} m")
sbt.check(np.array_equal(floor_origin(start), [0.0, 0.0, 0.0]), "Through Floor Origin: the floor stays at z = 0")
sbt.check(any("start below the floor" in t for t in warnings_of(start)),
          "Through Floor Origin: the body is lifted onto it, with the lift's warning")
sbt.check(abs(sbt.points_of(start)[:, 2].min()) < 0.02, "Through Floor Origin: lifted onto z = 0 at t = 0")
Delete(lifted)

# The jelly where the data puts it, above the floor.
for placement, expected_floor in (("Automatic", 0.0), ("Under the Body", 0.3)):
    body = SoftBody(Input=jelly, FloorPlacement=placement, EndTime=0.5)
    start, end = sbt.output_at(body, 0.0), sbt.points_of(sbt.output_at(body, 0.5))
    origin = floor_origin(start)
    print(f"{placement}, body above the floor: floor z {origin[2]:g}, lowest z at 0.5 s "
          f"{end[:, 2].min():.5f} m; warnings {warnings_of(start)}")
    sbt.check(abs(origin[2] - expected_floor) < 1e-12 and origin[0] == 0.0 and origin[1] == 0.0,
              f"{placement}: the floor is at z = {expected_floor}")
    sbt.check(not any("placed under the body" in t for t in warnings_of(start)),
              f"{placement}: no placement warning")
    sbt.check(expected_floor - 1e-9 <= end[:, 2].min() <= expected_floor + 0.02,
              f"{placement}: at 0.5 s it rests on the floor at z = {expected_floor}")
    Delete(body)

# Far away on a tilted floor: the plane passes through the lowest point along the unit normal.
far = moved([1.0e5, -2.0e5, -3.0])
far.UpdatePipeline()
x = sbt.points_of(far.GetClientSideObject().GetOutputDataObject(0))
body = SoftBody(Input=far, FloorNormal=[0.0, 1.0, 1.0], EndTime=0.1)
origin = floor_origin(sbt.output_at(body, 0.0))
n = np.array([0.0, 1.0, 1.0]) / np.sqrt(2.0)
heights = (x - origin) @ n
print(f"tilted, 100 km away: floor through {origin}, lowest height above it {heights.min():.3e} m")
sbt.check(abs(heights.min()) < 1e-9 * np.abs(x).max(), "the tilted floor passes through the lowest point")
sbt.check(not any("start below the floor" in t for t in warnings_of(sbt.output_at(body, 0.0))),
          "no point is left below it by rounding")
Delete(body)

capture = sbt.ErrorCapture()
bad = SoftBody(Input=jelly)
bad.GetProperty("FloorPlacement").SetElement(0, 7)  # past the enumeration, as a script can
bad.UpdateVTKObjects()
bad.UpdatePipeline(0.0)
capture.close()
print(f"FloorPlacement 7: {capture.errors}")
sbt.check(any("FloorPlacement" in e and "7" in e for e in capture.errors),
          "a FloorPlacement out of range is refused, quoting the value")
print("python.floor_placement: all checks passed")
