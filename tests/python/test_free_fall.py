"""python.free_fall: without floor and pins, the center of mass falls as g t^2 / 2.

Internal forces (springs, volume terms, damping) cancel in pairs, so the center of mass of the
body moves exactly under gravity whatever the material, by each integrator's own free-fall
recursion (Euler lags by g t dt / 2, Euler-Cromer leads by it, Midpoint and Verlet are exact),
checked to 1e-6 at t = 0.5 s and 1 s. Checked for every integrator and
for both material modes. The total mass must be Density * volume in Physical mode and TotalMass in
Raw Constants mode."""

import os

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())

reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
body = SoftBody(Input=reader, Floor=0, EndTime=1.0, FrameInterval=0.1)
g = np.array([0.0, 0.0, -9.81])
check_times = (0.5, 1.0)

# Rest volume of the input, for the mass check.
reader.UpdatePipeline()
rest = reader.GetClientSideObject().GetOutputDataObject(0)
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter  # noqa: E402
sizes = vtkCellSizeFilter()
sizes.SetInputData(rest)
sizes.ComputeSumOn()
sizes.Update()
volume = sizes.GetOutput().GetFieldData().GetArray("Volume").GetValue(0)


current = {}  # the Integrator set last (properties persist on the filter between cases)


def run_case(label, expected_mass, **properties):
    for name, value in properties.items():
        setattr(body, name, value)
    p0 = sbt.output_at(body, 0.0, sbt.PARTICLES_PORT)
    com0 = sbt.center_of_mass(p0)
    inverse_mass = sbt.point_array(p0, "InverseMass")
    sbt.check((inverse_mass > 0).all(), f"{label}: no point pinned")
    mass = (1.0 / inverse_mass).sum()
    sbt.check(sbt.isclose(mass, expected_mass, rel=1e-6),
              f"{label}: total mass {mass:.6g} kg = {expected_mass:.6g} kg")
    if "Integrator" in properties:
        current["Integrator"] = properties["Integrator"]
    integrator = current.get("Integrator", "Euler-Cromer")
    for t in check_times:
        particles = sbt.output_at(body, t, sbt.PARTICLES_PORT)
        mesh = sbt.output_at(body, t, sbt.MESH_PORT)
        com = sbt.center_of_mass(particles)
        moved = com - com0
        steps = sbt.field_value(mesh, "StepCount")
        h = sbt.field_value(mesh, "TimeStep")
        # Internal forces cancel in the center of mass, which therefore follows each
        # integrator's own free-fall recursion exactly (to rounding): Euler lags by g t h / 2,
        # Euler-Cromer leads by it, Midpoint and Verlet are exact; Verlet's velocity is the
        # half-step one, g (t - h / 2). 1e-6 is far below the integrators' O(h / t) ~ 1e-4.
        lead = {"Euler": -0.5 * h, "Euler-Cromer": 0.5 * h}.get(integrator, 0.0)
        expected = 0.5 * g * t * (t + 2.0 * lead)
        error = np.linalg.norm(moved - expected) / np.linalg.norm(expected)
        print(f"  {label}: t = {t} s, {steps:.0f} steps of {h:.3g} s: center of mass moved "
              f"{moved} m, expected {expected} m, relative error {error:.2e}")
        sbt.check(error < 1e-6, f"{label}: center-of-mass displacement at t = {t} s is the "
                                f"integrator's exact free fall ({error:.2e})")
        w = sbt.point_array(particles, "InverseMass")
        v = sbt.point_array(particles, "Velocity")
        com_velocity = (v / w[:, None]).sum(axis=0) / (1.0 / w).sum()
        expected_velocity = g * (t - 0.5 * h if integrator == "Verlet" else t)
        verror = np.linalg.norm(com_velocity - expected_velocity) / np.linalg.norm(expected_velocity)
        sbt.check(verror < 1e-6, f"{label}: center-of-mass velocity at t = {t} s is the "
                                 f"integrator's exact one ({com_velocity}, {verror:.2e})")


for integrator in ("Euler-Cromer", "Verlet", "Midpoint", "Euler"):
    run_case(f"Physical, {integrator}", 1100.0 * volume, Integrator=integrator)
run_case("Physical, stiff, Euler-Cromer", 2000.0 * volume, Integrator="Euler-Cromer",
         YoungsModulus=1e6, Density=2000.0)
# Raw constants sized for this 0.3 m body (k_D = 1 J): the defaults (100 J) on its 3 cm edges
# would need a step of ~0.5 us, minutes of simulation for nothing this test checks.
run_case("Raw Constants, Euler-Cromer", 3.0, MaterialMode="Raw Constants", TotalMass=3.0,
         DistanceStiffness=1.0, DistanceDamping=1e-3, VolumeStiffness=1.0, VolumeDamping=1e-3)
print("python.free_fall passed")
