"""python.floor_output: the Floor output port (port 4) is the floor plane as a square sized to
the body, so the GUI has a floor to show; it is empty with Floor off. Also: the Mesh's active
scalars are Velocity, which is what ParaView colours a new representation by."""

import math

from paraview.simple import *  # noqa: F401,F403 (the pvpython API, as users write it)

import softbody_testing as sbt

FLOOR_PORT = 4

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())
reader = XMLUnstructuredGridReader(FileName=[args.data_dir + "/jelly.vtu"])
body = SoftBody(Input=reader, EndTime=0.2)

rest = sbt.output_at(reader, 0.0)
b = rest.GetBounds()
diagonal = math.sqrt((b[1] - b[0]) ** 2 + (b[3] - b[2]) ** 2 + (b[5] - b[4]) ** 2)

floor = sbt.output_at(body, 0.0, FLOOR_PORT)
sbt.check(floor.GetNumberOfPoints() == 4 and floor.GetNumberOfPolys() == 1,
          f"the floor is one quad ({floor.GetNumberOfPoints()} points, "
          f"{floor.GetNumberOfPolys()} polygons)")
fb = floor.GetBounds()
sbt.check(fb[4] == 0.0 and fb[5] == 0.0, f"the floor lies in the plane z = 0 ({fb[4]}, {fb[5]})")
for axis in (0, 1):
    center = 0.5 * (b[2 * axis] + b[2 * axis + 1])
    sbt.check(sbt.isclose(fb[2 * axis], center - diagonal, rel=1e-12) and
              sbt.isclose(fb[2 * axis + 1], center + diagonal, rel=1e-12),
              f"axis {axis}: the floor spans the body's center +- its diagonal {diagonal:.4f} "
              f"({fb[2 * axis]:.4f}, {fb[2 * axis + 1]:.4f})")
normals = floor.GetPointData().GetNormals()
sbt.check(normals is not None and list(normals.GetTuple3(0)) == [0.0, 0.0, 1.0],
          "the floor's Normals are the floor normal")

# A later frame: the floor stays where it was (sized from the body at rest).
later = sbt.output_at(body, 0.2, FLOOR_PORT)
sbt.check(list(later.GetBounds()) == list(fb), "the floor does not move with the body")

# A tilted floor: every corner on the plane, the square centered under the body.
body.FloorNormal = [0.0, 1.0, 1.0]
body.FloorOrigin = [0.0, 0.0, -0.1]
tilted = sbt.output_at(body, 0.0, FLOOR_PORT)
n = [0.0, 1.0 / math.sqrt(2.0), 1.0 / math.sqrt(2.0)]
heights = [sum(n[k] * (p[k] - [0.0, 0.0, -0.1][k]) for k in range(3))
           for p in (tilted.GetPoint(i) for i in range(4))]
sbt.check(all(abs(h) < 1e-12 for h in heights), f"tilted floor: corners on the plane ({heights})")

body.Floor = 0
off = sbt.output_at(body, 0.0, FLOOR_PORT)
sbt.check(off.GetNumberOfPoints() == 0, "Floor off: the Floor port is empty")

mesh = sbt.output_at(body, 0.0)
scalars = mesh.GetPointData().GetScalars()
sbt.check(scalars is not None and scalars.GetName() == "Velocity",
          f"the Mesh's active scalars are Velocity ({scalars.GetName() if scalars else None})")
print("python.floor_output: all checks passed")
