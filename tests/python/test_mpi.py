"""python.mpi: `mpirun -np 2 pvbatch` gives the serial result.

Three bodies (the jelly and two shifted copies, in a row) are written to one .vtu with a point
array "OriginalId". This script (pvpython, one process) simulates them and then runs itself
under `mpirun -np 2 pvbatch --ranks`, where the reader's pieces go through RedistributeDataSet,
which cuts the middle body across the two ranks, into Soft Body. The distributed run must give every
point the serial position (matched by OriginalId; equal up to rounding, since the gathered
body's points are in another order, which changes the order of floating-point sums), the same
total mass, each body simulated whole on one rank, and both ranks busy.
"""

import json
import os
import shutil
import subprocess
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


def run_ranks():
    # The pvbatch side: rank 0 runs this script; the pipeline runs on both ranks, and the
    # writers write one piece per rank (what each rank simulated, with its ProcessId).
    ranks = vtkMultiProcessController.GetGlobalController().GetNumberOfProcesses()
    reader = XMLUnstructuredGridReader(FileName=[args.input])
    pieces = RedistributeDataSet(Input=reader)
    pieces.UpdatePipeline()
    body = SoftBody(Input=pieces, EndTime=END_TIME)
    CreateWriter(os.path.join(args.out, "mesh.pvtu"), ProcessIdScalars(Input=body)).UpdatePipeline(END_TIME)
    CreateWriter(os.path.join(args.out, "particles.pvtp"), OutputPort(body, 1)).UpdatePipeline(END_TIME)
    with open(os.path.join(args.out, "run.json"), "w") as info:
        json.dump({"ranks": ranks, "points_over_pieces": pieces.GetDataInformation().GetNumberOfPoints()}, info)


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

        # Serial reference, in this process.
        serial_body = SoftBody(Input=XMLUnstructuredGridReader(FileName=[two_bodies]), EndTime=END_TIME)
        serial = fetch_mesh(serial_body)
        serial_mass = sbt.field_value(serial, "TotalMass")

        # The same under MPI.
        result = os.path.join(work, "ranks")
        os.makedirs(result)
        # pvpython is an MPI singleton itself: its OMPI_/PMIX_ variables would make mpirun think it
        # runs inside a job, so the child starts from the environment without them.
        env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_"))}
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                   OMPI_MCA_btl="self,vader", OMPI_MCA_btl_vader_single_copy_mechanism="none",
                   OMPI_MCA_rmaps_base_oversubscribe="1")
        command = [mpirun, "-np", "2", pvbatch, os.path.abspath(__file__), "--ranks", "--plugin",
                   args.plugin, "--data-dir", args.data_dir, "--input", two_bodies, "--out", result]
        print("running:", " ".join(command), flush=True)
        run = subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True, timeout=240)
        print(run.stdout)
        sbt.check(run.returncode == 0, f"mpirun -np 2 pvbatch exited with {run.returncode}")
        reader = vtkXMLPUnstructuredGridReader()
        reader.SetFileName(os.path.join(result, "mesh.pvtu"))
        reader.Update()
        ranks_mesh = reader.GetOutput()
        with open(os.path.join(result, "run.json")) as info_file:
            info = json.load(info_file)
        sbt.check(info["ranks"] == 2, f"the pvbatch side ran on 2 ranks (got {info['ranks']})")

        # Every point once, at the serial position.
        serial_ids = sbt.point_array(serial, "OriginalId").astype(np.int64)
        ranks_ids = sbt.point_array(ranks_mesh, "OriginalId").astype(np.int64)
        sbt.check(sorted(ranks_ids.tolist()) == sorted(serial_ids.tolist()),
                  f"each of the {len(serial_ids)} points is output exactly once over the ranks "
                  f"(got {len(ranks_ids)} points)")
        serial_x = sbt.points_of(serial)[np.argsort(serial_ids)]
        ranks_x = sbt.points_of(ranks_mesh)[np.argsort(ranks_ids)]
        size = np.ptp(sbt.points_of(serial), axis=0).max()
        moved = np.abs(serial_x - sbt.points_of(both)).max()
        difference = np.abs(serial_x - ranks_x).max()
        print(f"body size {size:.3f} m, largest fall {moved:.4f} m, "
              f"largest serial/ranks difference {difference:.3g} m")
        sbt.check(moved > 0.01, "the bodies moved (the comparison is not of rest states)")
        sbt.check(difference <= 1e-9 * size,
                  f"every point ends where the serial run puts it (difference {difference:.3g} m)")

        # Whole bodies: all points of a body on one rank, and both ranks busy.
        rank = sbt.point_array(ranks_mesh, "ProcessId")[np.argsort(ranks_ids)]
        per_body = len(serial_ids) // BODIES
        body_ranks = [set(rank[k * per_body:(k + 1) * per_body].tolist()) for k in range(BODIES)]
        print(f"ranks of the bodies: {body_ranks}")
        sbt.check(all(len(r) == 1 for r in body_ranks), "each body is simulated whole on one rank")
        sbt.check(set().union(*body_ranks) == {0, 1}, "both ranks simulate bodies")
        sbt.check(info["points_over_pieces"] > len(serial_ids),
                  f"RedistributeDataSet really cut the bodies ({info['points_over_pieces']} points over the pieces "
                  f"for {len(serial_ids)}: interface points are in both)")

        particles = vtkXMLPPolyDataReader()
        particles.SetFileName(os.path.join(result, "particles.pvtp"))
        particles.Update()
        inverse = sbt.point_array(particles.GetOutput(), "InverseMass")
        ranks_mass = float(np.sum(1.0 / inverse[inverse > 0]))
        sbt.check(abs(ranks_mass - serial_mass) <= 1e-9 * serial_mass,
                  f"total mass over the ranks {ranks_mass:.6g} kg equals the serial {serial_mass:.6g} kg")
    finally:
            shutil.rmtree(work, ignore_errors=True)
    print("python.mpi passed")


# pvbatch must end its script normally (sys.exit there is an MPI abort), so no exits here but
# the skip.
if args.ranks:
    run_ranks()
else:
    run_serial_and_compare()
