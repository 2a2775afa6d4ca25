"""python.pbd: PBD and XPBD through pvpython, as a user scripts them.

1. Soft Body Cloth + Soft Body (XPBD, each solver): the pinned corners hold, the cloth hangs
   below them, and the Convergence port has one row per iteration.
2. The bundled jelly with XPBD falls onto the floor and rests on it, its volume kept within 2%.
3. Enumeration names are the pvpython API: Method, Solver by their labels."""

import os

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())

cloth = SoftBodyCloth(Resolution=[20, 20], TotalMass=0.1)
cloth.UpdatePipeline()
rest = sbt.points_of(cloth.GetClientSideObject().GetOutputDataObject(0))
pinned = np.flatnonzero(sbt.point_array(cloth.GetClientSideObject().GetOutputDataObject(0), "Pinned"))
sbt.check(len(pinned) == 2, f"the cloth pins two corners ({len(pinned)})")

for solver in ["Gauss-Seidel", "Jacobi", "Parallel Gauss-Seidel"]:
    body = SoftBody(Input=cloth, Method="XPBD", Solver=solver, Iterations=15,
                    PinnedPointsArray="Pinned", EndTime=1.0, FrameInterval=0.1)
    body.UpdatePipelineInformation()
    sbt.check(np.isclose(list(body.TimestepValues)[-1], 1.0), f"{solver}: times up to EndTime")
    mesh = sbt.output_at(body, 1.0)
    x = sbt.points_of(mesh)
    sbt.check(np.array_equal(x[pinned], rest[pinned]), f"{solver}: pinned corners did not move")
    # It swings down like a pendulum: at 0.6 s the free edge is near its lowest.
    swing = sbt.points_of(sbt.output_at(body, 0.6))
    sbt.check(swing[:, 2].min() < rest[:, 2].min() - 0.5,
              f"{solver}: the cloth swings below its corners (lowest z {swing[:, 2].min():.3f} m at 0.6 s)")
    table = sbt.output_at(body, 1.0, 2)
    sbt.check(table.GetNumberOfRows() == 15, f"{solver}: 15 convergence rows ({table.GetNumberOfRows()})")
    sbt.check(sbt.field_value(mesh, "Iterations") == 15, f"{solver}: Iterations field")
    Delete(body)

reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
jelly = SoftBody(Input=reader, Method="XPBD", Iterations=20, XPBDVolumeCompliance=0.0, EndTime=2.0)
jelly.UpdatePipelineInformation()
start = sbt.output_at(jelly, 0.0)
x0 = sbt.points_of(start)
end = sbt.output_at(jelly, 2.0)
x = sbt.points_of(end)
v = sbt.point_array(end, "Velocity")
ratio = sbt.cell_array(end, "VolumeRatio")
size = float(np.max(x0.max(axis=0) - x0.min(axis=0)))
print(f"jelly XPBD at 2 s: min z {x[:, 2].min():.4f} m, max speed {np.linalg.norm(v, axis=1).max():.4f} m/s, "
      f"VolumeRatio [{ratio.min():.4f}, {ratio.max():.4f}]\n{sbt.field_summary(end)}")
sbt.check(x[:, 2].min() > -1e-9, "no point below the floor")
# Resting means at the contact margin: automatic, a tenth of the mean surface edge length
# (3.7 mm for the jelly, 1.2 % of its size).
sbt.check(x[:, 2].min() < 0.02 * size, "the jelly rests on the floor (at its contact margin)")
sbt.check(abs(ratio.mean() - 1.0) < 0.02, f"volume kept within 2% (mean ratio {ratio.mean():.4f})")
sbt.check(np.linalg.norm(v, axis=1).max() < 0.2, "the jelly has come to rest")
