"""python.invalid_properties: out-of-range properties and unusable inputs give a VTK error and an
empty output, never a crash; correcting the value makes the filter work again. A body whose size
says it is not in meters is warned about."""

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
    lines = [line for line in text.strip().splitlines() if "must" in line or "got" in line]
    print(f"  captured for {label}: {lines[0].strip() if lines else text!r}")
    sbt.check(bool(errors.errors), f"{label}: a VTK error is reported")
    sbt.check(all(w in text for w in words), f"{label}: the error names {words}")
    sbt.check(out is None or out.GetNumberOfPoints() == 0, f"{label}: the output is empty")


expect_valid("valid settings")

# Each case: property values to set, and words the error must contain: the property's name and
# the value the user gave (setters never clamp, so the message quotes what was typed).
cases = [
    ({"EndTime": -1.0}, ["EndTime", "got -1"]),
    ({"EndTime": 0.0}, ["EndTime", "got 0"]),
    ({"FrameInterval": 0.0}, ["FrameInterval", "got 0"]),
    ({"FrameInterval": -0.1}, ["FrameInterval", "got -0.1"]),
    ({"TimeStep": float("nan")}, ["TimeStep", "got nan"]),
    ({"TimeStep": -0.01}, ["TimeStep", "got -0.01"]),
    ({"YoungsModulus": -5.0}, ["YoungsModulus", "got -5"]),
    ({"PoissonRatio": 0.5}, ["PoissonRatio", "[0, 0.5)", "got 0.5"]),
    ({"PoissonRatio": 0.7}, ["PoissonRatio", "got 0.7"]),
    ({"Density": 0.0}, ["Density", "got 0"]),
    ({"DampingTime": -1.0}, ["DampingTime", "got -1"]),
    ({"FloorNormal": [0.0, 0.0, 0.0]}, ["FloorNormal", "got (0, 0, 0)"]),
    ({"StrainLimit": 0.5}, ["StrainLimit", "got 0.5"]),
    ({"StrainLimit": 1.1, "StrainLimitIterations": 0}, ["StrainLimitIterations", "got 0"]),
    ({"MaxInverseMass": -2.0}, ["MaxInverseMass", "got -2"]),
    ({"MaterialMode": "Raw Constants", "TotalMass": 0.0}, ["TotalMass", "got 0"]),
    ({"PinnedPointsArray": "NoSuchArray"}, ["NoSuchArray"]),
    ({"CacheMemoryLimit": -1}, ["CacheMemoryLimit", "got -1"]),
    # Contacts, read by every method (Mass-Spring here).
    ({"CollisionMargin": -0.5}, ["CollisionMargin", "got -0.5"]),
    ({"StaticFriction": -1.0}, ["StaticFriction", "got -1"]),
    ({"DynamicFriction": -2.0}, ["DynamicFriction", "got -2"]),
    ({"Restitution": 1.5}, ["Restitution", "got 1.5"]),
    # PBD / XPBD settings, refused only under the method that reads them.
    ({"Method": "XPBD", "Iterations": 0}, ["Iterations", "got 0"]),
    ({"Method": "XPBD", "Substeps": 0}, ["Substeps", "got 0"]),
    ({"Method": "XPBD", "Relaxation": 2.5}, ["Relaxation", "(0, 2)", "got 2.5"]),
    ({"Method": "XPBD", "DynamicFriction": -1.0}, ["Friction", "got -1"]),
    ({"Method": "XPBD", "Restitution": 5.0}, ["Restitution", "[0, 1]", "got 5"]),
    ({"Method": "XPBD", "XPBDLinkCompliance": -1e-4}, ["XPBDLinkCompliance", "got -0.0001"]),
    ({"Method": "XPBD", "VelocityDamping": -3.0}, ["VelocityDamping", "got -3"]),
    ({"Method": "PBD", "PBDVolumeStiffness": 1.5}, ["PBDVolumeStiffness", "got 1.5"]),
    ({"Method": "XPBD", "BreakingStrain": -0.1}, ["BreakingStrain", "got -0.1"]),
    ({"Method": "XPBD", "Integrator": "Midpoint"}, ["Integrator", "Euler-Cromer", "Verlet"]),
    # Error-controlled steps (Mass-Spring and XPBD; PBD's stiffness changes with the step).
    ({"TimeStepMode": "Error-controlled", "ErrorTolerance": 0.0}, ["ErrorTolerance", "got 0"]),
    ({"TimeStepMode": "Error-controlled", "ErrorTolerance": -1e-3}, ["ErrorTolerance", "got -0.001"]),
    ({"TimeStepMode": "Error-controlled", "ErrorTolerance": 1e-20}, ["ErrorTolerance", "1e-20", "double precision"]),
    ({"TimeStepMode": "Error-controlled", "Integrator": "Static"}, ["Error-controlled", "Static"]),
    ({"Method": "PBD", "TimeStepMode": "Error-controlled"}, ["TimeStepMode 1", "XPBD"]),
    ({"Method": "XPBD", "TimeStepMode": "Error-controlled", "ErrorTolerance": 0.0}, ["ErrorTolerance", "got 0"]),
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

# A property the method ignores is not checked: Iterations under Mass-Spring.
body.Iterations = 0
expect_valid("Iterations = 0 under Mass-Spring (ignored)")
body.Iterations = 10

# CacheMemoryLimit 0 is accepted with a warning that caching is off.
body.CacheMemoryLimit = 0
expect_valid("CacheMemoryLimit = 0")
mesh = sbt.output_at(body, 0.1)
warnings = sbt.field_value(mesh, "Warnings") or ""
sbt.check("CacheMemoryLimit is 0" in warnings,
          f"CacheMemoryLimit = 0 is warned in field data Warnings ({warnings})")
body.CacheMemoryLimit = 512

# A requested time before 0 is clamped to the first frame: no error.
errors.clear()
out = sbt.output_at(body, -5.0)
sbt.check(not errors.errors and out.GetNumberOfPoints() > 0, "a time before 0 gives frame 0")
# A body in millimeters or centimeters (the jelly scaled by 1000 or 100) is simulated as meters,
# with a warning quoting its size, the factors and what its size would then be, which is the
# jelly's own; the jelly itself is not warned about.
errors.clear()
sbt.output_at(body, 0.1)
sbt.check(not any("m across" in w for w in errors.warnings), "the jelly (0.4 m) is not warned about its units")
reader.UpdatePipeline()
bounds = reader.GetDataInformation().GetBounds()
jelly_size = sum((bounds[2 * k + 1] - bounds[2 * k]) ** 2 for k in range(3)) ** 0.5
for unit, scale, factor in (("millimeters", 1000, "0.001"), ("centimeters", 100, "0.01")):
    rescaled = Transform(Input=reader)
    rescaled.Transform.Scale = [scale] * 3
    scaled = SoftBody(Input=rescaled, EndTime=0.1, FrameInterval=0.1, Floor=0)
    errors.clear()
    frame = sbt.output_at(scaled, 0.1)
    text = "".join(errors.warnings)
    listed = frame.GetFieldData().GetAbstractArray("Warnings")
    sbt.check(listed is not None and any("m across" in listed.GetValue(i) for i in range(listed.GetNumberOfValues())),
              f"the Warnings field data of the body in {unit} lists its units warning too")
    sbt.check("m across (its bounding-box diagonal): lengths are taken as meters" in text and unit in text
              and factor in text and f"{jelly_size:.3g}" in text,
              f"a body in {unit} is warned with its size, the remedy and the jelly's {jelly_size:.3g} m "
              f"({text.strip()[:300]!r})")
    Delete(scaled)
# The jelly in millimeters on the floor cannot carry its own weight either (about 200 m tall at
# E = 1e5 Pa): the Warnings field data says so with rho g H / E, which the jelly in meters is not
# told.
rescaled = Transform(Input=reader)
rescaled.Transform.Scale = [1000] * 3
standing = SoftBody(Input=rescaled, EndTime=0.1, FrameInterval=0.1)
listed = sbt.output_at(standing, 0.1).GetFieldData().GetAbstractArray("Warnings")
said = [listed.GetValue(i) for i in range(listed.GetNumberOfValues())] if listed else []
height = 1000 * (bounds[5] - bounds[4])
expected = standing.Density * 9.81 * height / standing.YoungsModulus
sbt.check(any("cannot carry its own weight" in w and f"{expected:.3g}" in w for w in said),
          f"the jelly in millimeters on the floor is told it cannot carry its weight "
          f"(rho g H / E = {expected:.3g}; {said!r:.300})")
listed = sbt.output_at(body, 0.1).GetFieldData().GetAbstractArray("Warnings")
sbt.check(not listed or not any("own weight" in listed.GetValue(i) for i in range(listed.GetNumberOfValues())),
          "the jelly in meters carries its weight")
Delete(standing)
errors.close()
print("python.invalid_properties passed")
