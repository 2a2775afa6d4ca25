"""python.gpu_device: Device = 'GPU (EGL)' from pvpython runs the same simulation as the CPU.

The jelly falls for 0.4 s on both devices; the GPU's points must match the CPU's within 1e-9 of
the body size (on Mesa's llvmpipe they are bitwise equal). Field data Device and GLRenderer say
where it ran. Where no EGL/OpenGL 4.3 context can be made the filter falls back to the CPU with
a warning: that is checked, and the test reports SKIP (77)."""

import os
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())

reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
# Frictionless: the GPU's floor is (the CPU's contacts then match it).
cpu = SoftBody(Input=reader, EndTime=0.4, StaticFriction=0.0, DynamicFriction=0.0)
gpu = SoftBody(Input=reader, EndTime=0.4, StaticFriction=0.0, DynamicFriction=0.0, Device="GPU (EGL)")
x_cpu = sbt.points_of(sbt.output_at(cpu, 0.4))
gpu_mesh = sbt.output_at(gpu, 0.4)
device = gpu_mesh.GetFieldData().GetAbstractArray("Device").GetValue(0)
renderer = gpu_mesh.GetFieldData().GetAbstractArray("GLRenderer").GetValue(0)
print(f"Device {device!r}, GLRenderer {renderer!r}")
if device != "GPU (EGL)":
    warnings = gpu_mesh.GetFieldData().GetAbstractArray("Warnings")
    text = " ".join(warnings.GetValue(i) for i in range(warnings.GetNumberOfValues()))
    sbt.check("GPU (EGL) is unavailable" in text, "the fallback says why in Warnings")
    print("SKIP: no EGL / OpenGL 4.3 context here")
    sys.exit(sbt.SKIP)
x_gpu = sbt.points_of(gpu_mesh)
size = float(np.max(x_cpu.max(axis=0) - x_cpu.min(axis=0)))
difference = float(np.abs(x_gpu - x_cpu).max())
sbt.check(difference <= 1e-9 * size, f"GPU matches CPU after 0.4 s (max difference {difference:.2e} m)")
sbt.check(renderer != "", "GLRenderer names the renderer")
x_rest = sbt.points_of(sbt.output_at(gpu, 0.0))
sbt.check(np.abs(x_gpu - x_rest).max() > 0.1, "the body fell (so the comparison is not of rest shapes)")
