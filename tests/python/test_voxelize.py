"""python.voxelize: Soft Body Voxelize and the Surface input/output from pvpython.

The bundled torus is voxelized (particle count against its volume within 2%), simulated with
XPBD and skinned: at t = 0 the Surface output is the torus exactly, at the end it rests on the
floor with its triangles and point count unchanged. The same surface skinned onto a TetGen
tet mesh of itself (a coarse body carrying a render mesh) reproduces it at t = 0 too."""

import os

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())

torus = XMLPolyDataReader(FileName=[os.path.join(args.data_dir, "torus.vtp")])
torus.UpdatePipeline()
surface = torus.GetClientSideObject().GetOutputDataObject(0)
rest = sbt.points_of(surface)

lattice = SoftBodyVoxelize(Input=torus, Spacing=0.02)
lattice.UpdatePipeline()
grid = lattice.GetClientSideObject().GetOutputDataObject(0)
volume = 2.490728e-02   # the torus polyhedron's volume (data/README.md)
expected = volume / 0.02 ** 3
sbt.check(abs(grid.GetNumberOfPoints() / expected - 1.0) < 0.02,
          f"{grid.GetNumberOfPoints()} particles for {expected:.0f} voxels of volume")

for name, body_input in [("lattice", lattice),
                         ("tets", TetrahedralizeSurfaceTetGen(Input=torus))]:
    body = SoftBody(Input=body_input, Surface=torus, Method="XPBD", EndTime=2.0)
    body.UpdatePipelineInformation()
    start = sbt.output_at(body, 0.0, 3)
    sbt.check(start.GetNumberOfPoints() == len(rest) and start.GetNumberOfCells() == surface.GetNumberOfCells(),
              f"{name}: the Surface output keeps the torus's points and triangles")
    error = np.abs(sbt.points_of(start) - rest).max()
    sbt.check(error < 1e-12, f"{name}: undeformed body reproduces the surface (max error {error:.1e} m)")
    end = sbt.points_of(sbt.output_at(body, 2.0, 3))
    print(f"{name}: surface z range at 2 s [{end[:, 2].min():.4f}, {end[:, 2].max():.4f}] m")
    sbt.check(end[:, 2].min() > -0.01 and end[:, 2].min() < 0.02,
              f"{name}: the skinned surface rests on the floor (lowest z {end[:, 2].min():.4f} m)")
