"""python.mpi: `mpirun -np 2 pvbatch` gives the serial result.

Three bodies (the jelly and two shifted copies, in a row) are written to one .vtu with a point
array "OriginalId". This script (pvpython, one process) simulates them and then runs itself
under `mpirun -np 2 pvbatch --ranks`, where the reader's pieces go through RedistributeDataSet,
which cuts the middle body across the two ranks, into Soft Body. The distributed run must give every
point the serial position (matched by OriginalId; equal up to rounding, since the gathered
body's points are in another order, which changes the order of floating-point sums), the same
total mass, and each body simulated whole on one rank. Five scenes:

- plain: the floor only; both ranks busy;
- obstacle: the bodies fall onto a large Sphere (Collisions = Obstacles) whose pieces the
  source would split over the ranks (it splits by longitude): every rank must meet the whole
  sphere; both ranks busy, and the sphere changes where the bodies end;
- bodies: the same with Collisions = Obstacles + Bodies: bodies on different ranks could not
  meet, so all of them are simulated on rank 0 (with a warning saying so);
- surface: the floor only, with the bodies' outer surface (Extract Surface of the reader) as
  the Surface input: rank 0 takes the whole Surface and every body, and the skinned Surface
  output must equal the serial one;
- conditions: a Soft Body Condition (a force on every point left of the row's middle) made on
  the ranks' pieces, whose set spans bodies on both ranks: the filter gathers it, and every
  point ends where the serial run puts it.
- floor_under: FloorPlacement Under the Body on a floor tilted along the row (FloorNormal
  0.3 0 1), whose lowest point is on one end body: every rank must place the floor through
  that point (reduced over the ranks), not through its own bodies' lowest.
"""

import json
import os
import shutil
import sys
import tempfile

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util import numpy_support
from vtkmodules.vtkCommonCore import vtkIdTypeArray
from vtkmodules.vtkFiltersCore import vtkAppendFilter
from vtkmodules.vtkIOXML import (vtkXMLPPolyDataReader, vtkXMLPUnstructuredGridReader,
                                  vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter)
from vtkmodules.vtkParallelCore import vtkMultiProcessController

import softbody_testing as sbt

END_TIME = 0.4
BODIES = 3


def extra_args(parser):
    parser.add_argument("--ranks", action="store_true", help="the pvbatch side (internal)")
    parser.add_argument("--input", help="the two-body .vtu (internal)")
    parser.add_argument("--out", help="where the pvbatch side writes its result (internal)")


args = sbt.parse_args(__doc__, extra_args)
# Under pvbatch the plugin must be loaded on every rank (remote=True), not only on rank 0.
LoadPlugin(args.plugin, remote=args.ranks, ns=globals())


def fetch_mesh(body):
    """The Mesh output at END_TIME, gathered from every rank onto this one."""
    body.UpdatePipeline(END_TIME)
    return servermanager.Fetch(body)


def write(grid, path):
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetInputData(grid)
    writer.SetFileName(path)
    writer.Write()


SCENES = ("plain", "obstacle", "bodies", "surface", "conditions", "floor_under")


def sphere_under_bodies(bounds):
    """A sphere of radius 1 m whose top is 0.1 m under the middle of the row of bodies: the
    middle body lands on its top, the outer ones on its flanks (other longitudes)."""
    centre_x = 0.5 * (bounds[0] + bounds[1])
    return Sphere(Radius=1.0, Center=[centre_x, 0.0, bounds[4] - 0.1 - 1.0], ThetaResolution=64,
                  PhiResolution=32)


def soft_body(scene, source, bounds, reader):
    if scene == "plain":
        return SoftBody(Input=source, EndTime=END_TIME)
    if scene == "conditions":
        # A force on every point left of the row's middle: the set spans the first body and
        # half of the middle one, which the ranks' pieces cut; each rank's condition sees its
        # piece only, and the filter gathers the set from every rank.
        push = SoftBodyCondition(Input=source, ConditionName="push", ConditionType="Force",
                                 Region="Half-space", PlaneOrigin=[0.5 * (bounds[0] + bounds[1]), 0, 0],
                                 PlaneNormal=[-1, 0, 0], Force=[0, 0, 0.05], ForceSpread="Per point")
        return SoftBody(Input=source, Conditions=[push], EndTime=END_TIME)
    if scene == "floor_under":
        return SoftBody(Input=source, FloorPlacement="Under the Body", FloorNormal=[0.3, 0.0, 1.0],
                        EndTime=END_TIME)
    if scene == "surface":
        # From the reader, not from the redistributed pieces (whose surfaces include the cuts).
        return SoftBody(Input=source, Surface=ExtractSurface(Input=reader), EndTime=END_TIME)
    collisions = "Obstacles" if scene == "obstacle" else "Obstacles + Bodies"
    return SoftBody(Input=source, Obstacles=[sphere_under_bodies(bounds)], Collisions=collisions,
                    EndTime=END_TIME)


def run_ranks():
    # The pvbatch side: rank 0 runs this script; the pipeline runs on both ranks, and the
    # writers write one piece per rank (what each rank simulated, with its ProcessId).
    ranks = vtkMultiProcessController.GetGlobalController().GetNumberOfProcesses()
    reader = XMLUnstructuredGridReader(FileName=[args.input])
    pieces = RedistributeDataSet(Input=reader)
    pieces.UpdatePipeline()
    bounds = reader.GetDataInformation().GetBounds()
    for scene in SCENES:
        body = soft_body(scene, pieces, bounds, reader)
        folder = os.path.join(args.out, scene)
        os.makedirs(folder, exist_ok=True)
        CreateWriter(os.path.join(folder, "mesh.pvtu"), ProcessIdScalars(Input=body)).UpdatePipeline(END_TIME)
        CreateWriter(os.path.join(folder, "particles.pvtp"), OutputPort(body, 1)).UpdatePipeline(END_TIME)
        if scene == "surface":
            CreateWriter(os.path.join(folder, "surface.pvtp"), OutputPort(body, 3)).UpdatePipeline(END_TIME)
        Delete(body)
    with open(os.path.join(args.out, "run.json"), "w") as info:
        json.dump({"ranks": ranks, "points_over_pieces": pieces.GetDataInformation().GetNumberOfPoints()}, info)


def compare_scene(scene, serial, rest, folder):
    """Checks one scene's ranks result against its serial one; returns the serial final points
    in OriginalId order."""
    serial_mass = sbt.field_value(serial, "TotalMass")
    reader = vtkXMLPUnstructuredGridReader()
    reader.SetFileName(os.path.join(folder, "mesh.pvtu"))
    reader.Update()
    ranks_mesh = reader.GetOutput()

    # Every point once, at the serial position.
    serial_ids = sbt.point_array(serial, "OriginalId").astype(np.int64)
    ranks_ids = sbt.point_array(ranks_mesh, "OriginalId").astype(np.int64)
    sbt.check(sorted(ranks_ids.tolist()) == sorted(serial_ids.tolist()),
              f"{scene}: each of the {len(serial_ids)} points is output exactly once over the ranks "
              f"(got {len(ranks_ids)} points)")
    serial_x = sbt.points_of(serial)[np.argsort(serial_ids)]
    ranks_x = sbt.points_of(ranks_mesh)[np.argsort(ranks_ids)]
    size = np.ptp(sbt.points_of(serial), axis=0).max()
    moved = np.abs(serial_x - sbt.points_of(rest)).max()
    difference = np.abs(serial_x - ranks_x).max()
    print(f"{scene}: body size {size:.3f} m, largest fall {moved:.4f} m, "
          f"largest serial/ranks difference {difference:.3g} m")
    sbt.check(moved > 0.01, f"{scene}: the bodies moved (the comparison is not of rest states)")
    sbt.check(difference <= 1e-9 * size,
              f"{scene}: every point ends where the serial run puts it (difference {difference:.3g} m)")

    # Whole bodies: all points of a body on one rank; both ranks busy unless the bodies collide.
    rank = sbt.point_array(ranks_mesh, "ProcessId")[np.argsort(ranks_ids)]
    per_body = len(serial_ids) // BODIES
    body_ranks = [set(rank[k * per_body:(k + 1) * per_body].tolist()) for k in range(BODIES)]
    print(f"{scene}: ranks of the bodies: {body_ranks}")
    sbt.check(all(len(r) == 1 for r in body_ranks), f"{scene}: each body is simulated whole on one rank")
    if scene in ("bodies", "surface"):
        sbt.check(set().union(*body_ranks) == {0}, f"{scene}: the bodies are all on rank 0")
    else:
        sbt.check(set().union(*body_ranks) == {0, 1}, f"{scene}: both ranks simulate bodies")

    particles = vtkXMLPPolyDataReader()
    particles.SetFileName(os.path.join(folder, "particles.pvtp"))
    particles.Update()
    inverse = sbt.point_array(particles.GetOutput(), "InverseMass")
    ranks_mass = float(np.sum(1.0 / inverse[inverse > 0]))
    sbt.check(abs(ranks_mass - serial_mass) <= 1e-9 * serial_mass,
              f"{scene}: total mass over the ranks {ranks_mass:.6g} kg equals the serial {serial_mass:.6g} kg")
    return serial_x


def compare_surface(serial, folder):
    """The skinned Surface output of the ranks (all on rank 0) against the serial one, point by
    point through the OriginalId the surface carries from the reader."""
    reader = vtkXMLPPolyDataReader()
    reader.SetFileName(os.path.join(folder, "surface.pvtp"))
    reader.Update()
    ranks = reader.GetOutput()

    def used(surface):
        """OriginalId and position of the points the surface's polygons use (Extract Surface
        keeps the unused interior points in one process and drops them in pvbatch)."""
        connectivity = numpy_support.vtk_to_numpy(surface.GetPolys().GetConnectivityArray())
        points = np.unique(connectivity)
        ids = sbt.point_array(surface, "OriginalId").astype(np.int64)[points]
        order = np.argsort(ids)
        return ids[order], sbt.points_of(surface)[points][order]

    serial_ids, serial_x = used(serial)
    ranks_ids, ranks_x = used(ranks)
    sbt.check(len(serial_ids) > 0 and np.array_equal(ranks_ids, serial_ids),
              f"surface: the {len(serial_ids)} skinned vertices are output once over the ranks "
              f"(got {len(ranks_ids)})")
    size = np.ptp(serial_x, axis=0).max()
    difference = np.abs(serial_x - ranks_x).max()
    print(f"surface: {len(serial_ids)} skinned vertices, largest serial/ranks difference {difference:.3g} m")
    sbt.check(difference <= 1e-9 * size, f"surface: the skinned Surface equals the serial one ({difference:.3g} m)")


def run_serial_and_compare():
    mpirun = shutil.which("mpirun")
    pvbatch = shutil.which("pvbatch")
    if not mpirun or not pvbatch:
        print(f"SKIP: mpirun ({mpirun}) or pvbatch ({pvbatch}) not found")
        sys.exit(sbt.SKIP)

    work = tempfile.mkdtemp(prefix="softbody_mpi_")
    try:
        # Three bodies in a row along x, in one grid, each point numbered. RedistributeDataSet
        # cuts the row at its middle, through the middle body.
        jelly = vtkXMLUnstructuredGridReader()
        jelly.SetFileName(os.path.join(args.data_dir, "jelly.vtu"))
        jelly.Update()
        append = vtkAppendFilter()
        for k in range(BODIES):
            copy = jelly.GetOutput().NewInstance()
            copy.DeepCopy(jelly.GetOutput())
            xyz = numpy_support.vtk_to_numpy(copy.GetPoints().GetData())
            xyz[:, 0] += k * 1.5 * (xyz[:, 0].max() - xyz[:, 0].min())
            copy.GetPoints().Modified()
            append.AddInputData(copy)
        append.Update()
        both = append.GetOutput()
        ids = vtkIdTypeArray()
        ids.SetName("OriginalId")
        ids.SetNumberOfValues(both.GetNumberOfPoints())
        for i in range(both.GetNumberOfPoints()):
            ids.SetValue(i, i)
        both.GetPointData().AddArray(ids)
        two_bodies = os.path.join(work, "two_bodies.vtu")
        write(both, two_bodies)

        # Serial references, in this process.
        serial_reader = XMLUnstructuredGridReader(FileName=[two_bodies])
        serial_reader.UpdatePipeline()
        bounds = serial_reader.GetDataInformation().GetBounds()
        serial = {}
        for scene in SCENES:
            body = soft_body(scene, serial_reader, bounds, serial_reader)
            serial[scene] = fetch_mesh(body)
            if scene == "surface":
                serial_surface = servermanager.Fetch(body, idx=3)
            Delete(body)

        # The same under MPI.
        result = os.path.join(work, "ranks")
        os.makedirs(result)
        command = [mpirun, "-np", "2", pvbatch, os.path.abspath(__file__), "--ranks", "--plugin",
                   args.plugin, "--data-dir", args.data_dir, "--input", two_bodies, "--out", result]
        output = sbt.run_under_mpirun(command, timeout=240)
        with open(os.path.join(result, "run.json")) as info_file:
            info = json.load(info_file)
        sbt.check(info["ranks"] == 2, f"the pvbatch side ran on 2 ranks (got {info['ranks']})")
        sbt.check(info["points_over_pieces"] > both.GetNumberOfPoints(),
                  f"RedistributeDataSet really cut the bodies ({info['points_over_pieces']} points over the pieces "
                  f"for {both.GetNumberOfPoints()}: interface points are in both)")
        sbt.check("must meet each other: all 3 bodies are simulated on rank 0 of 2" in output,
                  "the bodies scene says that its colliding bodies stay on rank 0")
        sbt.check("Surface is skinned onto the bodies: all 3 bodies are simulated on rank 0 of 2" in output,
                  "the surface scene says that its skinned bodies stay on rank 0")

        final = {}
        for scene in SCENES:
            final[scene] = compare_scene(scene, serial[scene], both, os.path.join(result, scene))
        compare_surface(serial_surface, os.path.join(result, "surface"))
        obstacle_effect = np.abs(final["obstacle"] - final["plain"]).max()
        print(f"the sphere moves the bodies' final points by up to {obstacle_effect:.3f} m")
        sbt.check(obstacle_effect > 0.05, "the bodies land on the sphere (the obstacle scene is not the plain one)")
        push_effect = np.abs(final["conditions"] - final["plain"]).max()
        sbt.check(push_effect > 1e-3, f"the force condition moves the bodies (by up to {push_effect:.3f} m)")
        floor_effect = np.abs(final["floor_under"] - final["plain"]).max()
        sbt.check(floor_effect > 0.05, f"the floor under the bodies changes where they end (by up to {floor_effect:.3f} m)")
    finally:
            shutil.rmtree(work, ignore_errors=True)
    print("python.mpi passed")


# pvbatch must end its script normally (sys.exit there is an MPI abort), so no exits here but
# the skip.
if args.ranks:
    run_ranks()
else:
    run_serial_and_compare()
