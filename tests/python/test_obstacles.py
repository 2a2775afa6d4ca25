"""python.obstacles: the Soft Body filter's Obstacles input and collision properties in pvpython.

The jelly dropped onto a Sphere source (floor off) stays outside it, and falls into it with
Collisions = Off (so the check can fail); a time-dependent obstacle (a Programmable Source wall
that moves with the requested time) pushes a body along the floor; bad collision values are
refused with a message quoting them; Device = GPU (EGL) with an obstacle runs on the CPU and
says why in Warnings; the bundled torus, voxelized and dropped onto a sphere, draws its skinned
Surface outside the sphere (within the contact margin), which the skin alone would not."""

import builtins
import math
import os
import textwrap

import numpy as np
import vtk
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())


# In a function: the Programmable Source's scripts run in __main__ and overwrite module-level
# names there (x, t, all, ...).
def main():
    reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
    reader.UpdatePipeline()
    bounds = reader.GetDataInformation().GetBounds()
    size = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])
    center_xy = (0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]))

    # 1. A sphere twice the body's size, its top a quarter size below the body; no floor. The
    # sphere's triangles lie inside the true sphere by at most r (1 - cos(pi / 16)) (32 x 32).
    radius = size
    center = (center_xy[0] + 0.1 * size, center_xy[1], bounds[4] - 0.25 * size - radius)
    sphere = Sphere(Center=center, Radius=radius, ThetaResolution=32, PhiResolution=32)
    inscribed = radius * math.cos(math.pi / 16)
    nearest = {}
    for collisions in ["Obstacles", "Off"]:
        body = SoftBody(Input=reader, Obstacles=[sphere], Floor=0, Collisions=collisions,
                        EndTime=0.8, FrameInterval=0.04)
        closest = float("inf")
        for t in [0.2, 0.4, 0.6, 0.8]:
            x = sbt.points_of(sbt.output_at(body, t))
            closest = min(closest, float(np.linalg.norm(x - np.array(center), axis=1).min()))
        nearest[collisions] = closest
        if collisions == "Obstacles":
            plan = sbt.field_value(sbt.output_at(body, 0.8), "Plan") or ""
            sbt.check("collision detection: obstacles" in plan, f"the plan lists the obstacles ({plan!r})")
        Delete(body)
    print(f"nearest point to the sphere's centre: {nearest} (inscribed radius {inscribed:.4f} m)")
    sbt.check(nearest["Obstacles"] >= inscribed - 1e-9, "the body stays outside the sphere")
    sbt.check(nearest["Off"] < inscribed - 0.1 * size, "with Collisions Off it falls into the sphere")

    # 2. A moving wall (normal +x) at x = x0 + 0.5 t pushes the body along a frictionless floor.
    x0 = bounds[0] - 0.1
    wall = ProgrammableSource(OutputDataSetType="vtkPolyData")
    wall.ScriptRequestInformation = textwrap.dedent("""
    import vtk
    self.GetOutputInformation(0).Set(vtk.vtkStreamingDemandDrivenPipeline.TIME_RANGE(), [0.0, 100.0], 2)
    """)
    wall.Script = textwrap.dedent(f"""
    import vtk
    info = self.GetOutputInformation(0)
    t = info.Get(vtk.vtkStreamingDemandDrivenPipeline.UPDATE_TIME_STEP()) if info.Has(
        vtk.vtkStreamingDemandDrivenPipeline.UPDATE_TIME_STEP()) else 0.0
    x = {x0!r} + 0.5 * t
    points = vtk.vtkPoints()
    for y, z in [(-10, -10), (10, -10), (10, 10), (-10, 10)]:
        points.InsertNextPoint(x, y, z)
    quad = vtk.vtkCellArray()
    quad.InsertNextCell(4, [0, 1, 2, 3])
    output = self.GetPolyDataOutput()
    output.SetPoints(points)
    output.SetPolys(quad)
    """)
    pushed = SoftBody(Input=reader, Obstacles=[wall], StaticFriction=0.0, DynamicFriction=0.0,
                      FloorOrigin=[0.0, 0.0, bounds[4] - 1e-3], EndTime=1.0, FrameInterval=0.04)
    mesh = sbt.output_at(pushed, 0.8)
    x = sbt.points_of(mesh)
    wall_x = x0 + 0.5 * 0.8
    v = sbt.point_array(mesh, "Velocity")
    print(f"wall at x = {wall_x:.4f} m, body from x = {x[:, 0].min():.4f} m, mean x velocity "
          f"{v[:, 0].mean():.3f} m/s")
    sbt.check(x[:, 0].min() > wall_x, "the body is in front of the moving wall")
    sbt.check(x[:, 0].min() > bounds[0] + 0.1 * size, "the wall has pushed the body along")
    sbt.check(v[:, 0].mean() > 0.45, "the body moves with the wall (0.5 m/s)")

    # 3. Bad values are refused, quoting them.
    errors = sbt.ErrorCapture()
    for name, value, words in [("CollisionMargin", -0.5, ["CollisionMargin", "got -0.5"]),
                               ("StaticFriction", -1.0, ["StaticFriction", "got -1"]),
                               ("Restitution", 2.0, ["Restitution", "got 2"])]:
        body = SoftBody(Input=reader, Obstacles=[sphere], EndTime=0.2, FrameInterval=0.1)
        setattr(body, name, value)
        errors.clear()
        out = sbt.output_at(body, 0.1)
        text = "".join(errors.errors)
        # builtins: the Programmable Source's numpy helpers replaced all() in __main__.
        sbt.check(builtins.all(w in text for w in words), f"{name} = {value} is refused naming {words}")
        sbt.check(out is None or out.GetNumberOfPoints() == 0, f"{name} = {value}: the output is empty")
        Delete(body)

    # 4. Device GPU (EGL) with an obstacle: simulated on the CPU, and Warnings says why.
    errors.clear()
    gpu = SoftBody(Input=reader, Obstacles=[sphere], Device="GPU (EGL)", EndTime=0.2, FrameInterval=0.1)
    mesh = sbt.output_at(gpu, 0.1)
    warnings = sbt.field_value(mesh, "Warnings") or ""
    sbt.check(sbt.field_value(mesh, "Device") == "CPU", "Device GPU with obstacles runs on the CPU")
    sbt.check("simulating on the CPU" in warnings and "Obstacles input" in warnings,
              f"Warnings says why ({warnings!r})")
    errors.close()

    # 5. The skinned Surface of a voxelized body stays outside the obstacle it lands on. The
    # torus's surface is extrapolated beyond its lattice's outer particles, so where the ring
    # bends over the sphere the skin alone draws it inside; the render correction puts those
    # vertices onto the sphere, and the filter reports how many it moved and how deep they were.
    torus = XMLPolyDataReader(FileName=[os.path.join(args.data_dir, "torus.vtp")])
    spacing = 0.03
    lattice = SoftBodyVoxelize(Input=torus, Spacing=spacing)
    ball = Triangulate(Input=Sphere(Center=[0.1, 0.0, 0.0], Radius=0.25, ThetaResolution=32, PhiResolution=32))
    ball.UpdatePipeline()
    distance = vtk.vtkImplicitPolyDataDistance()  # signed, negative inside (outward normals)
    distance.SetInput(ball.GetClientSideObject().GetOutputDataObject(0))
    margin = 0.1 * 0.5 * spacing  # automatic: a tenth of the particle radius
    for method in ["PBD", "XPBD"]:
        body = SoftBody(Input=lattice, Surface=torus, Obstacles=[ball], Floor=0, Method=method,
                        EndTime=0.4, FrameInterval=0.05)
        deepest_drawn, moved, deepest_corrected = 0.0, 0, 0.0
        for t in [0.2, 0.25, 0.3, 0.35, 0.4]:
            skinned = sbt.output_at(body, t, 3)
            inside = -builtins.min(distance.EvaluateFunction(x) for x in sbt.points_of(skinned))
            deepest_drawn = builtins.max(deepest_drawn, inside)
            moved += int(sbt.field_value(skinned, "SkinnedMovedOutOfObstacles"))
            deepest_corrected = builtins.max(deepest_corrected, sbt.field_value(skinned, "SkinnedDeepestInObstacles"))
        print(f"{method}: skinned torus on a sphere, 0.2-0.4 s: deepest vertex drawn {deepest_drawn:.2e} m "
              f"inside (margin {margin:.2e} m); the correction moved {moved} vertices, the deepest "
              f"from {deepest_corrected:.4f} m inside")
        sbt.check(deepest_drawn <= margin, f"{method}: the skinned Surface is no deeper than the margin "
                  f"inside the obstacle ({deepest_drawn:.2e} m)")
        sbt.check(moved > 0 and deepest_corrected > 2 * margin,
                  f"{method}: without the correction the skin would draw vertices deeper than the margin "
                  f"({moved} moved, deepest {deepest_corrected:.4f} m)")
        Delete(body)
    print("python.obstacles passed")


main()
