"""python.gpu_device: Device = 'GPU (EGL)' from pvpython runs the same simulation as the CPU.

The jelly falls onto the floor and lands on both devices at the default settings (floor
friction included); the GPU's points must match the CPU's within 1e-9 of the body size on
Mesa's llvmpipe (they are bitwise equal there), within 2e-4 on a hardware GPU, whose fused
multiply-adds can turn a contact's stick-or-slide decision at its threshold (unit.gpu_* tests
state the measured bounds). The GPU run gives no warning. Stable Neo-Hookean and Corotated run on
the GPU with the same result; VolumetricFormulation Nodal Average falls back to the CPU naming
itself. A Fixed and a Force condition run on the GPU with the CPU's states and Reaction arrays;
a Pressure falls back naming itself. Field data Device and GLRenderer say
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
END = 0.8
cpu = SoftBody(Input=reader, EndTime=END)
gpu = SoftBody(Input=reader, EndTime=END, Device="GPU (EGL)")
x_cpu = sbt.points_of(sbt.output_at(cpu, END))
gpu_mesh = sbt.output_at(gpu, END)
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
bound = 1e-9 if "llvmpipe" in renderer or "softpipe" in renderer else 2e-4
sbt.check(difference <= bound * size,
          f"GPU matches CPU after {END} s at the defaults (max difference {difference:.2e} m, bound {bound:g} of {size:.3f} m)")
sbt.check(renderer != "", "GLRenderer names the renderer")
x_rest = sbt.points_of(sbt.output_at(gpu, 0.0))
sbt.check(np.abs(x_gpu - x_rest).max() > 0.1, "the body fell (so the comparison is not of rest shapes)")
floor_gap = float(x_gpu[:, 2].min())
sbt.check(abs(floor_gap) < 0.05 * size, f"the body reached the floor (lowest point at {floor_gap:.2e} m, the contact margin)")
frictionless = SoftBody(Input=reader, EndTime=END, StaticFriction=0.0, DynamicFriction=0.0)
friction_moves = float(np.abs(sbt.points_of(sbt.output_at(frictionless, END)) - x_cpu).max())
sbt.check(friction_moves > 1e-6 * size, f"friction acted in the compared run (moves points by {friction_moves:.2e} m)")
warnings = gpu_mesh.GetFieldData().GetAbstractArray("Warnings")
texts = [warnings.GetValue(i) for i in range(warnings.GetNumberOfValues())] if warnings else []
sbt.check(not any("GPU" in t for t in texts), f"no device warning at the defaults ({texts!r})")

# The finite-element models run on the GPU too, with the same result (Corotated to rounding: its
# rotation comes from another SVD algorithm than the CPU's); Nodal Average falls back to the CPU
# and says why.
for model in ("Stable Neo-Hookean", "Corotated"):
    cpu_fe = SoftBody(Input=reader, EndTime=END, MaterialModel=model)
    gpu_fe = SoftBody(Input=reader, EndTime=END, MaterialModel=model, Device="GPU (EGL)")
    gpu_fe_mesh = sbt.output_at(gpu_fe, END)
    sbt.check(gpu_fe_mesh.GetFieldData().GetAbstractArray("Device").GetValue(0) == "GPU (EGL)",
              f"{model} ran on the GPU")
    fe_difference = float(np.abs(sbt.points_of(gpu_fe_mesh) - sbt.points_of(sbt.output_at(cpu_fe, END))).max())
    sbt.check(fe_difference <= bound * size,
              f"{model}: GPU matches CPU after {END} s (max difference {fe_difference:.2e} m)")
    sbt.check(gpu_fe_mesh.GetCellData().GetArray("VonMisesStress") is not None,
              f"VonMisesStress comes out of the GPU run ({model})")
gpu_nodal = sbt.output_at(SoftBody(Input=reader, EndTime=0.1, MaterialModel="Corotated",
                                   VolumetricFormulation="Nodal Average", Device="GPU (EGL)"), 0.1)
sbt.check(gpu_nodal.GetFieldData().GetAbstractArray("Device").GetValue(0) == "CPU", "Nodal Average ran on the CPU")
warnings = gpu_nodal.GetFieldData().GetAbstractArray("Warnings")
texts = [warnings.GetValue(i) for i in range(warnings.GetNumberOfValues())] if warnings else []
sbt.check(any("GPU (EGL) is unavailable" in t and "Nodal Average" in t for t in texts),
          f"the Nodal Average fallback names itself ({texts!r})")

# Conditions through the filter: the jelly held by its bottom (Fixed) and pushed sideways at its
# top (Force) runs on the GPU with the CPU's states and reactions; a Pressure falls back.
bounds = reader.GetDataInformation().GetBounds()
bottom = SoftBodyCondition(Input=reader, ConditionName="bottom", ConditionType="Fixed", Region="Half-space",
                           PlaneOrigin=[0, 0, bounds[4] + 0.01 * size], PlaneNormal=[0, 0, -1])
push = SoftBodyCondition(Input=reader, ConditionName="push", ConditionType="Force", Region="Half-space",
                         PlaneOrigin=[0, 0, bounds[5] - 0.1 * size], PlaneNormal=[0, 0, 1], Force=[2.0, 0, 0])
held_meshes = {}
for device in ("CPU", "GPU (EGL)"):
    held_meshes[device] = sbt.output_at(SoftBody(Input=reader, EndTime=0.3, Conditions=[bottom, push],
                                                 Device=device), 0.3)
held_gpu, held_cpu = held_meshes["GPU (EGL)"], held_meshes["CPU"]
sbt.check(held_gpu.GetFieldData().GetAbstractArray("Device").GetValue(0) == "GPU (EGL)",
          "Fixed and Force conditions ran on the GPU")
held_difference = float(np.abs(sbt.points_of(held_gpu) - sbt.points_of(held_cpu)).max())
sbt.check(held_difference <= bound * size, f"conditions: GPU matches CPU after 0.3 s (max difference {held_difference:.2e} m)")
reaction_cpu = sbt.point_array(held_cpu, "Reaction")
reaction_gpu = sbt.point_array(held_gpu, "Reaction")
largest = float(np.abs(reaction_cpu).max())
sbt.check(largest > 0.1, f"the support reacts ({largest:.3f} N at most)")
sbt.check(float(np.abs(reaction_gpu - reaction_cpu).max()) <= 1e-6 * largest, "conditions: the GPU's Reaction is the CPU's")
inflate = SoftBodyCondition(Input=reader, ConditionName="inflate", ConditionType="Pressure", Region="Half-space",
                            PlaneOrigin=[0, 0, bounds[5] - 0.1 * size], PlaneNormal=[0, 0, 1], Pressure=100.0)
pressed = sbt.output_at(SoftBody(Input=reader, EndTime=0.1, Conditions=[bottom, inflate], Device="GPU (EGL)"), 0.1)
sbt.check(pressed.GetFieldData().GetAbstractArray("Device").GetValue(0) == "CPU", "a Pressure condition ran on the CPU")
warnings = pressed.GetFieldData().GetAbstractArray("Warnings")
texts = [warnings.GetValue(i) for i in range(warnings.GetNumberOfValues())] if warnings else []
sbt.check(any("GPU (EGL) is unavailable" in t and '"inflate"' in t for t in texts),
          f"the Pressure fallback names the condition ({texts!r})")
