"""python.lab_scenes: the accuracy lab's reference scenes through the Soft Body filter.

The same scenes as tests/bench/bench_accuracy.cpp, built here as a user would (a tet box written
to a .vtu, read, filtered), checked against their closed forms with tolerances that follow from
the step, not from a run:

1. Free fall, PBD and XPBD (Young's modulus), 4 substeps of a 1/60 s step: both predict with
   symplectic Euler, whose centre of mass after N substeps of h has fallen exactly
   g h^2 N (N + 1) / 2 = g t (t + h) / 2: checked to 1e-9, and its distance from the analytic
   g t^2 / 2 is then h / t (a first-order lead).
2. The hanging bar (2 x 2 x 10 cells of 2 cm, E 1e5 Pa, nu 0.25, rho 1000, top face pinned),
   Implicit Euler run to rest: the elongation against rho g L^2 / (2E). At rest the step no
   longer matters (steps of 0.05 and 0.1 s agree to 1e-6 of it); the model (the mass-spring
   network, not elasticity) may be off by a few percent: within 10%. Doubling E must halve it
   (linear elasticity; the 1% strain bends that by about 1%: within 2%).
3. The incline (PBD, a 2 x 2 x 1-cell block of 5 cm on a floor tilted 30 deg, mu 0.3, 0.5 s):
   acceleration g (sin theta - mu cos theta) from the distance slid, 2 s / t^2. The error of a
   first-order method is C h: at 8 and 32 substeps it must fall by about 4 (2.5 to 6.5), and the
   Richardson extrapolation (4 a_32 - a_8) / 3, which removes the C h term, must be within a
   quarter of a_32's error of the closed form. Tilted 20 deg with mu 0.5 (tan theta < mu) the
   block sticks, up to a creep that is first order in the substep (falls by about 4 from 8 to 32
   substeps) and below 10 h / t of the frictionless distance.
"""

import math
import os
import tempfile

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())

G = 9.81
workdir = tempfile.mkdtemp(prefix="softbody_lab_")


def tet_box(nx, ny, nz, cell, origin=(0.0, 0.0, 0.0), rotation=None, pinned=None):
    return sbt.write_tet_box(workdir, nx, ny, nz, cell, origin, rotation, pinned)


def run(path, end, **properties):
    """Soft Body on the file at `path`; the Mesh and Particles outputs at `end`."""
    reader = XMLUnstructuredGridReader(FileName=[path])
    body = SoftBody(Input=reader, EndTime=end, FrameInterval=end, **properties)
    return sbt.output_at(body, 0.0, sbt.PARTICLES_PORT), sbt.output_at(body, end), \
        sbt.output_at(body, end, sbt.PARTICLES_PORT)


# 1. Free fall --------------------------------------------------------------------------------
path, _ = tet_box(2, 2, 2, 0.05, origin=(0.0, 0.0, 1.0))
t = 0.5
for method, extra in (("PBD", {}), ("XPBD", {"XPBDMaterial": "Young's Modulus"})):
    start, mesh, particles = run(path, t, Method=method, Floor=0, Substeps=4, Iterations=2, **extra)
    step = sbt.field_value(mesh, "TimeStep")
    h = step / 4
    fallen = sbt.center_of_mass(start)[2] - sbt.center_of_mass(particles)[2]
    recursion = 0.5 * G * t * (t + h)
    analytic = 0.5 * G * t * t
    print(f"  free fall, {method}: step {step:.4g} s / 4 substeps; fell {fallen:.9f} m, symplectic "
          f"Euler's g t (t + h) / 2 = {recursion:.9f} m, analytic {analytic:.9f} m")
    sbt.check(abs(fallen - recursion) < 1e-9 * recursion,
              f"free fall, {method}: the centre of mass follows symplectic Euler exactly")
    sbt.check(abs((fallen - analytic) / analytic - h / t) < 1e-6,
              f"free fall, {method}: it leads g t^2 / 2 by h / t = {h / t:.4g}")

# 2. The hanging bar --------------------------------------------------------------------------
cell, length, rho = 0.02, 0.2, 1000.0


def hanging_elongation(youngs, step):
    path, points = tet_box(2, 2, 10, cell, pinned=lambda p: p[2] > length - 1e-9)
    bottom = points[:, 2] < 1e-9
    _, mesh, _ = run(path, 10.0, Method="Mass-Spring", Integrator="Implicit Euler", TimeStep=step,
                     ImplicitTolerance=1e-9, ImplicitMaxIterations=200, Floor=0,
                     PinnedPointsArray="Pinned", YoungsModulus=youngs, PoissonRatio=0.25, Density=rho,
                     DampingTime=1e-5)
    return -float(sbt.point_array(mesh, "Displacement")[bottom, 2].mean())


E = 1.0e5
elasticity = rho * G * length * length / (2 * E)
at_rest = hanging_elongation(E, 0.05)
at_rest_coarser = hanging_elongation(E, 0.1)
stiffer = hanging_elongation(2 * E, 0.05)
print(f"  hanging bar: elongation {at_rest * 1e3:.5f} mm (steps of 0.1 s: {at_rest_coarser * 1e3:.5f} mm), "
      f"elasticity rho g L^2 / (2E) = {elasticity * 1e3:.5f} mm: model error "
      f"{100 * (at_rest - elasticity) / elasticity:+.2f}%; E doubled: {stiffer * 1e3:.5f} mm")
sbt.check(abs(at_rest - at_rest_coarser) < 1e-6 * at_rest, "hanging bar: at rest (the step does not matter)")
sbt.check(abs(at_rest - elasticity) < 0.1 * elasticity, "hanging bar: within 10% of rho g L^2 / (2E)")
sbt.check(abs(at_rest / stiffer - 2.0) < 0.04, "hanging bar: twice E, half the elongation (within 2%)")

# 3. The incline ------------------------------------------------------------------------------


def slid_on_incline(theta_degrees, mu, substeps):
    theta = math.radians(theta_degrees)
    c, s = math.cos(theta), math.sin(theta)
    rotation = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    path, _ = tet_box(2, 2, 1, 0.05, origin=(-0.05, -0.05, 1e-6), rotation=rotation)
    start, mesh, particles = run(path, t, Method="PBD", Floor=1, FloorOrigin=[0, 0, 0],
                                 FloorNormal=list(rotation @ [0, 0, 1]), StaticFriction=mu, DynamicFriction=mu,
                                 Substeps=substeps, Iterations=1)
    downhill = rotation @ [1, 0, 0]
    moved = sbt.center_of_mass(particles) - sbt.center_of_mass(start)
    return float(np.dot(moved, downhill)), sbt.field_value(mesh, "TimeStep") / substeps


theta, mu = 30.0, 0.3
exact = G * (math.sin(math.radians(theta)) - mu * math.cos(math.radians(theta)))
accelerations, steps = {}, {}
for substeps in (8, 32):
    slid, h = slid_on_incline(theta, mu, substeps)
    accelerations[substeps], steps[substeps] = 2 * slid / (t * t), h
    print(f"  incline {theta} deg, mu {mu}, {substeps} substeps of {h:.4g} s: a = "
          f"{accelerations[substeps]:.5f} m/s^2 against g (sin - mu cos) = {exact:.5f} "
          f"({100 * (accelerations[substeps] - exact) / exact:+.2f}%)")
error8, error32 = (abs(accelerations[n] - exact) for n in (8, 32))
richardson = (4 * accelerations[32] - accelerations[8]) / 3
print(f"  incline: error ratio 8 / 32 substeps {error8 / error32:.2f}; Richardson {richardson:.5f} m/s^2 "
      f"({100 * (richardson - exact) / exact:+.3f}%)")
sbt.check(2.5 < error8 / error32 < 6.5, "incline: the error is first order in the substep (falls by ~4)")
sbt.check(abs(richardson - exact) < 0.25 * error32,
          "incline: the extrapolation to h = 0 is the closed form g (sin theta - mu cos theta)")

frictionless = 0.5 * G * math.sin(math.radians(20.0)) * t * t
creep = {}
for substeps in (8, 32):
    slid, h = slid_on_incline(20.0, 0.5, substeps)
    creep[substeps] = abs(slid) / frictionless
    print(f"  incline 20 deg, mu 0.5, {substeps} substeps: slid {slid * 1e3:.4f} mm, {creep[substeps]:.2e} "
          f"of the frictionless {frictionless * 1e3:.1f} mm (h / t = {h / t:.2e})")
# Static friction holds the contact where it first touched (position level), so the creep falls
# at least as fast as the substep (it measured second order: 16x for 4x smaller substeps).
sbt.check(creep[8] / creep[32] > 2.5, "incline: tan theta < mu, the block sticks up to a creep "
          "that vanishes with the substep (at least first order)")
sbt.check(creep[32] < 10 * h / t, "incline: the creep is within 10 h / t of the frictionless slide")
print("python.lab_scenes passed")
