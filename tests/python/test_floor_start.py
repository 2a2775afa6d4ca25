"""python.floor_start: a body that starts half below the floor is put on it, not launched.

The bundled torus, voxelized and centred on the floor plane z = 0 (FloorPlacement Through
Floor Origin; Automatic would place the floor under it: python.floor_placement), is simulated
with PBD and XPBD for 1 s. Without pre-stabilization it would leave at 23 m/s and be 18 m up after 1 s;
instead it is lifted onto the floor at t = 0 without velocity, with a warning, and never rises
above that start; its lowest point stays on the floor."""

import os

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())

torus = XMLPolyDataReader(FileName=[os.path.join(args.data_dir, "torus.vtp")])
torus.UpdatePipeline()
bounds = torus.GetDataInformation().GetBounds()
centred = Transform(Input=torus)
centred.Transform.Translate = [0.0, 0.0, -0.5 * (bounds[4] + bounds[5])]
lattice = SoftBodyVoxelize(Input=centred, Spacing=0.03)

for method in ("PBD", "XPBD"):
    body = SoftBody(Input=lattice, Method=method, EndTime=1.0, FloorPlacement="Through Floor Origin")
    body.UpdatePipelineInformation()
    start = sbt.output_at(body, 0.0)
    x0 = sbt.points_of(start)
    warnings = start.GetFieldData().GetAbstractArray("Warnings")
    texts = [warnings.GetValue(i) for i in range(warnings.GetNumberOfValues())] if warnings else []
    sbt.check(any("start below the floor" in t for t in texts),
              f"{method}: a warning names the points below the floor: {texts}")
    # Voxelized particles keep half the spacing (their radius) from the floor, plus the
    # automatic contact margin (a tenth of the particle radius).
    sbt.check(abs(x0[:, 2].min() - 1.1 * 0.015) < 1e-9, f"{method}: lifted onto the floor at t = 0 "
              f"(lowest z {x0[:, 2].min():.5f} m, particle radius 0.015 m + margin 0.0015 m)")
    top = x0[:, 2].max()
    com0 = sbt.center_of_mass(sbt.output_at(body, 0.0, sbt.PARTICLES_PORT))[2]
    highest, rising, fastest = com0, 0.0, 0.0
    for t in list(body.TimestepValues)[1::5]:
        particles = sbt.output_at(body, t, sbt.PARTICLES_PORT)
        v = sbt.point_array(particles, "Velocity")
        m = 1.0 / sbt.point_array(particles, "InverseMass")
        highest = max(highest, sbt.center_of_mass(particles)[2])
        rising = max(rising, float((m * v[:, 2]).sum() / m.sum()))
        fastest = max(fastest, float(v[:, 2].max()))
    # Points may move up as the ring settles and tips; its centre of mass must not.
    print(f"{method}: centre of mass at start {com0:.4f} m (top {top:.4f} m), highest "
          f"{highest:.4f} m, its largest upward speed {rising:.3f} m/s (any point: {fastest:.3f} m/s)")
    sbt.check(highest < com0 + 1e-3, f"{method}: never rises above its start ({highest:.4f} m)")
    sbt.check(rising < 0.5, f"{method}: no upward launch ({rising:.3f} m/s)")
    Delete(body)
