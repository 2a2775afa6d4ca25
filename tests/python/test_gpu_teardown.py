"""python.gpu_teardown: several GPU filters, updated, then a plain end of the script.

Eight Soft Body filters (the four integrators on Device CPU and on Device 'GPU (EGL)') stay
alive together on one mesh; each is updated and each GPU result is compared with its CPU twin.
Two more GPU filters are created, updated and deleted in between. The script then simply ends:
no os._exit. pvpython must tear everything down (the filters die in ParaView's own finalization)
and exit with status 0, not abort in free() at teardown ('corrupted size vs. prev_size') or
hang, as GL torn down in the wrong order can (gpu/src/shared_gl_context.h). SKIP (77) where no
EGL / OpenGL 4.3 context exists (the filter then falls back to the CPU, which
python.gpu_device checks)."""

import os
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())

END = 0.05
reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])

probe = SoftBody(Input=reader, EndTime=END, Device="GPU (EGL)")
if sbt.field_value(sbt.output_at(probe, END), "Device") != "GPU (EGL)":
    print("SKIP: no EGL / OpenGL 4.3 context here")
    sys.exit(sbt.SKIP)  # a plain exit: the CPU fallback holds no GPU state
Delete(probe)
del probe

filters = []
for integrator in ["Euler", "Midpoint", "Verlet", "Euler-Cromer"]:
    cpu = SoftBody(Input=reader, EndTime=END, Integrator=integrator, Device="CPU")
    gpu = SoftBody(Input=reader, EndTime=END, Integrator=integrator, Device="GPU (EGL)")
    filters.append((integrator, cpu, gpu))
    # One more GPU filter created, updated and deleted while the others live.
    transient = SoftBody(Input=reader, EndTime=END, Integrator=integrator, Device="GPU (EGL)")
    sbt.output_at(transient, END)
    Delete(transient)
    del transient

for integrator, cpu, gpu in filters:  # all eight alive, updated in turns
    x_cpu = sbt.points_of(sbt.output_at(cpu, END))
    gpu_mesh = sbt.output_at(gpu, END)
    sbt.check(sbt.field_value(gpu_mesh, "Device") == "GPU (EGL)", f"{integrator} ran on the GPU")
    difference = float(np.abs(sbt.points_of(gpu_mesh) - x_cpu).max())
    sbt.check(difference <= 1e-9, f"{integrator}: GPU matches CPU (max difference {difference:.2e} m)")

print("ending the script with eight filters alive (no os._exit)", flush=True)
