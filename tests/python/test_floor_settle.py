"""python.floor_settle: the jelly falls onto the floor z = 0 and comes to rest there.

At EndTime every point is above the floor (within a small tolerance), the body touches it, its
center of mass has come down by about the drop height, no tetrahedron is inverted, and the
velocities are small (the body has settled)."""

import os

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())

reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
body = SoftBody(Input=reader)   # defaults: floor at z = 0, gravity -9.81 z, EndTime 3 s
body.UpdatePipelineInformation()
times = list(body.TimestepValues)
end = times[-1]

start_mesh = sbt.output_at(body, 0.0)
start_particles = sbt.output_at(body, 0.0, sbt.PARTICLES_PORT)
x0 = sbt.points_of(start_mesh)
com0 = sbt.center_of_mass(start_particles)
size = float(np.max(x0.max(axis=0) - x0.min(axis=0)))
drop = float(x0[:, 2].min())   # height of the lowest point above the floor
print(f"start: {len(x0)} points, size {size:.3f} m, lowest point {drop:.3f} m above the floor, "
      f"center of mass z {com0[2]:.4f} m")

mesh = sbt.output_at(body, end)
particles = sbt.output_at(body, end, sbt.PARTICLES_PORT)
print(f"field data at t = {end}:\n{sbt.field_summary(mesh)}")
x = sbt.points_of(mesh)
v = sbt.point_array(mesh, "Velocity")
u = sbt.point_array(mesh, "Displacement")
ratio = sbt.cell_array(mesh, "VolumeRatio")
com = sbt.center_of_mass(particles)
speed = np.linalg.norm(v, axis=1)
com_velocity = (v / sbt.point_array(particles, "InverseMass")[:, None]).sum(axis=0) / \
    (1.0 / sbt.point_array(particles, "InverseMass")).sum()
print(f"end: min z {x[:, 2].min():.5f} m, center of mass z {com[2]:.4f} m, "
      f"max speed {speed.max():.4f} m/s, mean speed {speed.mean():.4f} m/s, "
      f"center-of-mass velocity {com_velocity}, VolumeRatio [{ratio.min():.3f}, {ratio.max():.3f}]")

floor_tolerance = 1e-3 * size
sbt.check(sbt.isclose(sbt.field_value(mesh, "SimulationTime"), end, rel=1e-9),
          f"the output is the frame at EndTime = {end} s")
sbt.check(mesh.GetNumberOfPoints() == len(x0) and mesh.GetNumberOfCells() == start_mesh.GetNumberOfCells(),
          "the mesh keeps its topology")
sbt.check(particles.GetNumberOfPoints() == len(x0), "one particle per mesh point")
sbt.check(np.allclose(u, x - x0, atol=1e-9), "Displacement = current - rest positions")
sbt.check(x[:, 2].min() >= -floor_tolerance,
          f"every point is above the floor z = 0 within {floor_tolerance:.1e} m "
          f"(lowest {x[:, 2].min():.2e} m)")
# Touching means within the contact margin: automatic, a tenth of the mean surface edge length
# (3.7 mm for the jelly, 1.2 % of its size).
sbt.check(x[:, 2].min() <= 0.02 * size, "the body rests on the floor (lowest point touches it)")
sbt.check(com0[2] - com[2] > 0.8 * drop,
          f"the center of mass came down by about the drop height {drop:.3f} m "
          f"({com0[2] - com[2]:.3f} m)")
sbt.check(ratio.min() > 0.5 and ratio.max() < 1.5,
          "no tetrahedron inverted or badly crushed at rest (VolumeRatio in [0.5, 1.5])")
# Settled: an impact speed of sqrt(2 g h) ~ 2.4 m/s has decayed by two orders of magnitude.
settle_speed = 0.02 * np.sqrt(2.0 * 9.81 * drop)
sbt.check(speed.max() < settle_speed,
          f"the body has settled: max speed {speed.max():.4f} < {settle_speed:.4f} m/s")
# With floor friction (0.3 by default) the still-rocking body's base sticks while its top
# sways, so the centre of mass sways too (1.6 cm/s at 3 s, measured).
sbt.check(np.linalg.norm(com_velocity) < settle_speed,
          f"center of mass at rest ({np.linalg.norm(com_velocity):.2e} m/s)")
sbt.check(np.allclose(sbt.points_of(particles), x, atol=1e-12),
          "the particles sit on the mesh points")
print("python.floor_settle passed")
