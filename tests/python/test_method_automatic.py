"""python.method_automatic: Method Automatic, the default, runs what the input's cells need.

- the jelly's tets: Mass-Spring, silently (field data Method), every frame equal bit for bit to
  Method = Mass-Spring's;
- the voxelized torus (line cells only) and a Soft Body Cloth (lines and quads): XPBD, with a
  warning that quotes the body's link count, equal bit for bit to Method = XPBD's (where
  Mass-Spring refuses them);
- a Method out of range is refused naming Automatic among the values.
"""
import os

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())


def method_and_warnings(frame):
    method = frame.GetFieldData().GetAbstractArray("Method").GetValue(0)
    array = frame.GetFieldData().GetAbstractArray("Warnings")
    return method, [array.GetValue(i) for i in range(array.GetNumberOfValues())] if array else []


def links_of(source):
    source.UpdatePipeline()
    data = source.GetClientSideObject().GetOutputDataObject(0)
    return sum(1 for c in range(data.GetNumberOfCells()) if data.GetCellType(c) in (3, 4))


jelly = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
torus = XMLPolyDataReader(FileName=[os.path.join(args.data_dir, "torus.vtp")])
lattice = SoftBodyVoxelize(Input=torus)
cloth = SoftBodyCloth()
for name, source, expected, t in (("jelly", jelly, "Mass-Spring", 0.4), ("voxelized torus", lattice, "XPBD", 0.3),
                                  ("cloth", cloth, "XPBD", 0.3)):
    automatic = SoftBody(Input=source, EndTime=t)
    sbt.check(automatic.Method == "Automatic", f"{name}: Method is Automatic by default")
    frame = sbt.output_at(automatic, t)
    method, warnings = method_and_warnings(frame)
    chose = [w for w in warnings if "Method Automatic chose" in w]
    print(f"{name}: ran {method}; {chose}")
    sbt.check(method == expected, f"{name}: Automatic ran {expected} (field data Method: {method})")
    if expected == "XPBD":
        links = links_of(source)
        sbt.check(len(chose) == 1 and f"{links} links" in chose[0],
                  f"{name}: a warning says Automatic chose XPBD, quoting its {links} links")
    else:
        sbt.check(not chose, f"{name}: nothing to say for a tet mesh")
    explicit = SoftBody(Input=source, Method=expected, EndTime=t)
    same = sbt.points_of(sbt.output_at(explicit, t))
    sbt.check(np.array_equal(sbt.points_of(frame), same),
              f"{name}: at t = {t} s every point equals Method = {expected}'s bit for bit")
    sbt.check(np.abs(same - sbt.points_of(sbt.output_at(explicit, 0.0))).max() > 1e-3,
              f"{name}: the body moved (the comparison is not of rest states)")
    Delete(explicit)
    Delete(automatic)

capture = sbt.ErrorCapture()
bad = SoftBody(Input=jelly)
bad.GetProperty("Method").SetElement(0, 7)
bad.UpdateVTKObjects()
bad.UpdatePipeline(0.0)
capture.close()
print(f"Method 7: {capture.errors[:1]}")
sbt.check(any("Method must be one of" in e and "3 (Automatic)" in e and "got 7" in e for e in capture.errors),
          "a Method out of range is refused, naming Automatic and quoting the value")
print("python.method_automatic: all checks passed")
