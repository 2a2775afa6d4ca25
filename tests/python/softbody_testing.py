"""Shared helpers for the pvpython tests in tests/python (imported by the test scripts).

Every test script is run as

    pvpython tests/python/test_<name>.py --plugin <build>/.../SoftBody.so --data-dir <repo>/data

(see tests/python/CMakeLists.txt). A failed check raises AssertionError, which makes pvpython exit
with a non-zero status; SKIP (77) is returned where something optional is missing.

All data access goes through the client-side VTK objects, which is valid in pvpython's built-in
session (no separate pvserver): `proxy.UpdatePipeline(t)` then
`proxy.GetClientSideObject().GetOutputDataObject(port)`. servermanager.Fetch() is not used: it
updates its reduction filter without a time, so it does not return the frame at time t.
"""

import argparse
import math
import os
import sys

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow, vtkPoints
from vtkmodules.vtkCommonDataModel import VTK_TETRA, vtkUnstructuredGrid
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

SKIP = 77

MESH_PORT = 0       # "Mesh": the deformed vtkUnstructuredGrid
PARTICLES_PORT = 1  # "Particles": vtkPolyData vertices with Velocity and InverseMass
CONVERGENCE_PORT = 2  # "Convergence": vtkTable of the last step's residual per iteration


def parse_args(description, extra=None):
    """Parse the common --plugin / --data-dir arguments (plus extra(parser) ones)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--plugin", default=os.environ.get("SOFTBODY_PLUGIN_FILE"),
                        help="path to the built SoftBody.so")
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("--data-dir", default=os.path.join(here, "..", "..", "data"),
                        help="the project's data/ folder")
    if extra:
        extra(parser)
    args = parser.parse_args()
    if not args.plugin:
        parser.error("--plugin (or SOFTBODY_PLUGIN_FILE) is required")
    if not os.path.isfile(args.plugin):
        fail(f"plugin not found: {args.plugin} (build the project first)")
    return args


def mpi_environment():
    """The environment for an `mpirun` started from pvpython: pvpython is an MPI singleton
    itself, and its OMPI_/PMIX_ variables would make mpirun think it runs inside a job, so the
    child starts without them (as root, oversubscribed, shared-memory transport only)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_"))}
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_btl="self,vader", OMPI_MCA_btl_vader_single_copy_mechanism="none",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    return env


def run_under_mpirun(command, timeout):
    """Runs `command` (an mpirun command line) in mpi_environment(), prints its output, checks that
    it exits with 0 and returns the output."""
    import subprocess
    print("running:", " ".join(command), flush=True)
    run = subprocess.run(command, env=mpi_environment(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, timeout=timeout)
    print(run.stdout)
    check(run.returncode == 0, f"{' '.join(command[:4])} ... exited with {run.returncode}")
    return run.stdout


def fail(message):
    print("FAILED:", message, file=sys.stderr)
    sys.exit(1)


def check(condition, message):
    """Print the check and its outcome; raise AssertionError when it does not hold."""
    print(("ok    " if condition else "FAIL  ") + message, flush=True)
    if not condition:
        raise AssertionError(message)


class ErrorCapture:
    """Collects the VTK error (and warning) messages sent to the output window.

    vtkOutputWindow invokes ErrorEvent / WarningEvent with the message text as call data, so an
    observer on the global instance sees every vtkErrorMacro of every algorithm and executive.
    The messages still get printed as usual.
    """

    def __init__(self):
        self.errors = []
        self.warnings = []
        self._window = vtkOutputWindow.GetInstance()

        @calldata_type(VTK_STRING)
        def on_error(_obj, _event, text):
            self.errors.append(text)

        @calldata_type(VTK_STRING)
        def on_warning(_obj, _event, text):
            self.warnings.append(text)

        # Keep references: the observers hold only weak links to Python callables' owners.
        self._callbacks = (on_error, on_warning)
        self._tags = [self._window.AddObserver(vtkCommand.ErrorEvent, on_error),
                      self._window.AddObserver(vtkCommand.WarningEvent, on_warning)]

    def clear(self):
        self.errors.clear()
        self.warnings.clear()

    def close(self):
        for tag in self._tags:
            self._window.RemoveObserver(tag)
        self._tags = []


def output_at(proxy, time, port=MESH_PORT):
    """The filter's output on `port` at `time`, as a deep copy (later updates don't change it)."""
    proxy.UpdatePipeline(time)
    data = proxy.GetClientSideObject().GetOutputDataObject(port)
    if data is None:
        return None
    copy = data.NewInstance()
    copy.DeepCopy(data)
    return copy


def points_of(dataset):
    if dataset is None or dataset.GetPoints() is None:
        return np.zeros((0, 3))
    return numpy_support.vtk_to_numpy(dataset.GetPoints().GetData()).astype(np.float64)


def point_array(dataset, name):
    array = dataset.GetPointData().GetArray(name)
    if array is None:
        raise AssertionError(f"point array '{name}' missing from {dataset.GetClassName()}; "
                             f"has {array_names(dataset.GetPointData())}")
    return numpy_support.vtk_to_numpy(array).astype(np.float64)


def cell_array(dataset, name):
    array = dataset.GetCellData().GetArray(name)
    if array is None:
        raise AssertionError(f"cell array '{name}' missing; has {array_names(dataset.GetCellData())}")
    return numpy_support.vtk_to_numpy(array).astype(np.float64)


def array_names(attributes):
    return [attributes.GetArrayName(i) for i in range(attributes.GetNumberOfArrays())]


def field_value(dataset, name):
    """The first value of a field-data array (number or string), or None when absent."""
    field = dataset.GetFieldData()
    array = field.GetAbstractArray(name)
    if array is None or array.GetNumberOfValues() == 0:
        return None
    if array.IsA("vtkStringArray"):
        return "\n".join(array.GetValue(i) for i in range(array.GetNumberOfValues()))
    if array.GetNumberOfComponents() == 1 and array.GetNumberOfTuples() == 1:
        return array.GetTuple1(0)
    return numpy_support.vtk_to_numpy(array)


def field_summary(dataset):
    lines = []
    field = dataset.GetFieldData()
    for i in range(field.GetNumberOfArrays()):
        name = field.GetAbstractArray(i).GetName()
        value = field_value(dataset, name)
        if isinstance(value, float):
            value = f"{value:.6g}"
        lines.append(f"  {name}: {value}")
    return "\n".join(lines)


def center_of_mass(particles):
    """Mass-weighted center of the particles (InverseMass > 0 ones; pinned have 0)."""
    x = points_of(particles)
    w = point_array(particles, "InverseMass")
    free = w > 0.0
    m = 1.0 / w[free]
    return (x[free] * m[:, None]).sum(axis=0) / m.sum()


def isclose(a, b, rel=1e-9, abs_=1e-12):
    return math.isclose(a, b, rel_tol=rel, abs_tol=abs_)


def write_tet_box(workdir, nx, ny, nz, cell, origin=(0.0, 0.0, 0.0), rotation=None, pinned=None):
    """A box of nx x ny x nz cubes, each split into 6 tets around its main diagonal (Kuhn), as a
    .vtu file in `workdir`; `pinned(p)` marks points for a "Pinned" array. Returns the path and the points."""
    index = lambda i, j, k: (k * (ny + 1) + j) * (nx + 1) + i  # noqa: E731
    points = np.array([[i * cell, j * cell, k * cell] for k in range(nz + 1) for j in range(ny + 1)
                       for i in range(nx + 1)], dtype=float) + np.asarray(origin, dtype=float)
    # The six paths from corner 0 to corner 7 of a unit cube, one axis at a time.
    paths = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
    tets = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                for path in paths:
                    corner = [i, j, k]
                    tet = [index(*corner)]
                    for axis in path:
                        corner[axis] += 1
                        tet.append(index(*corner))
                    a, b, c, d = (points[t] for t in tet)
                    if np.dot(b - a, np.cross(c - a, d - a)) < 0:  # positive orientation
                        tet[2], tet[3] = tet[3], tet[2]
                    tets.append(tet)
    if rotation is not None:
        points = points @ rotation.T
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_support.numpy_to_vtk(points, deep=True))
    grid.SetPoints(vtk_points)
    for tet in tets:
        grid.InsertNextCell(VTK_TETRA, 4, tet)
    if pinned is not None:
        flags = numpy_support.numpy_to_vtk(np.array([1 if pinned(p) else 0 for p in points], dtype=np.int32),
                                           deep=True)
        flags.SetName("Pinned")
        grid.GetPointData().AddArray(flags)
    path = os.path.join(workdir, f"box_{nx}x{ny}x{nz}_{len(os.listdir(workdir))}.vtu")
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(grid)
    writer.Write()
    return path, points
