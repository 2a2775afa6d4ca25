"""python.invalid_properties: out-of-range properties and unusable inputs give a VTK error and an
empty output, never a crash; correcting the value makes the filter work again."""

import os

from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())

reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
body = SoftBody(Input=reader, EndTime=0.2, FrameInterval=0.1)
errors = sbt.ErrorCapture()


def expect_valid(label):
    errors.clear()
    out = sbt.output_at(body, 0.1)
    sbt.check(not errors.errors, f"{label}: no error ({errors.errors[:1]})")
    sbt.check(out is not None and out.GetNumberOfPoints() > 0, f"{label}: output has points")


def expect_error(label, words, time=0.1):
    errors.clear()
    out = sbt.output_at(body, time)
    text = "".join(errors.errors)
    print(f"  captured for {label}: {text.strip().splitlines()[1] if text.count(chr(10)) else text!r}")
    sbt.check(bool(errors.errors), f"{label}: a VTK error is reported")
    sbt.check(all(w in text for w in words), f"{label}: the error names {words}")
    sbt.check(out is None or out.GetNumberOfPoints() == 0, f"{label}: the output is empty")


expect_valid("valid settings")

# Each case: property values to set, words the error must contain, the values to restore.
cases = [
    ({"EndTime": -1.0}, ["EndTime"]),
    ({"EndTime": 0.0}, ["EndTime"]),
    ({"FrameInterval": 0.0}, ["FrameInterval"]),
    ({"FrameInterval": -0.1}, ["FrameInterval"]),
    ({"TimeStep": float("nan")}, ["TimeStep"]),
    ({"YoungsModulus": -5.0}, ["YoungsModulus"]),
    ({"PoissonRatio": 0.5}, ["PoissonRatio"]),
    ({"Density": 0.0}, ["Density"]),
    ({"FloorNormal": [0.0, 0.0, 0.0]}, ["FloorNormal"]),
    ({"StrainLimit": 0.5}, ["StrainLimit"]),
    ({"MaterialMode": "Raw Constants", "TotalMass": 0.0}, ["TotalMass"]),
    ({"PinnedPointsArray": "NoSuchArray"}, ["NoSuchArray"]),
]
for values, words in cases:
    # Copy the values: getattr returns a live property, which would follow the bad value.
    saved = {}
    for name in values:
        value = getattr(body, name)
        saved[name] = value if isinstance(value, (str, int, float)) else list(value)
    label = ", ".join(f"{k}={v!r}" for k, v in values.items())
    for name, value in values.items():
        setattr(body, name, value)
    expect_error(label, words)
    for name, value in saved.items():
        setattr(body, name, value)
    expect_valid(f"after restoring from {label}")

# An input the filter cannot simulate: hexahedra (voxels), not tetrahedra.
voxels = Threshold(Input=Wavelet(WholeExtent=[0, 2, 0, 2, 0, 2]), Scalars=["POINTS", "RTData"],
                   LowerThreshold=-1e30, UpperThreshold=1e30)
body.Input = voxels
expect_error("hexahedral input", ["tetrahedra"])
body.Input = reader
expect_valid("tetrahedral input again")

# A requested time before 0 is clamped to the first frame: no error.
errors.clear()
out = sbt.output_at(body, -5.0)
sbt.check(not errors.errors and out.GetNumberOfPoints() > 0, "a time before 0 gives frame 0")
errors.close()
print("python.invalid_properties passed")
