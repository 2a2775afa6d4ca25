"""Run time against error on your own mesh and scene: a grid of Soft Body variants.

    from paraview.simple import *
    LoadPlugin(".../SoftBody.so", remote=False, ns=globals())
    from softbody import sweep

    reader = XMLUnstructuredGridReader(FileName=["my_part.vtu"])
    def my_scene():                       # a new Soft Body of your scene, each call
        return SoftBody(Input=reader, YoungsModulus=2e6, PinnedPointsArray="Fixed")

    table = sweep.run(my_scene,
                      grid={"Integrator": ["BDF2", "Implicit Euler"],
                            "TimeStep": [1 / 60, 1 / 240, 1 / 960]},
                      end_time=1.0, frame_interval=0.1, output_dir="my_sweep")

Each variant (every combination of the grid's values, set on a new proxy from `my_scene()`)
runs to `end_time` frame by frame. Measured: the set-up (the first frame, t = 0: reading,
checking and preparing the body) and the run (every later frame) as wall time, and the error
against a reference run: the largest distance of any point from where the reference puts it,
over the frames [m]. The reference is `reference` (property values on top of the scene;
default: BDF2 with error-controlled steps at a tolerance of 1e-5 of the body's size per second,
ImplicitTolerance 1e-8). Written
to `output_dir`: `sweep.csv` (one row per variant: its values, status, set-up and run seconds,
error) and `sweep.png` (run time against error, the Pareto front joined: the variants no other
one beats in both). A variant that fails (a refused value, a blow-up) is recorded with its
message and the sweep goes on. Progress is printed per variant.

Refused before anything runs: a property the Soft Body filter does not have (the valid ones are
listed), and a value outside an enumeration property's choices (listed).

Over MPI ranks: run the same script under `mpirun -np N pvbatch --symmetric my_sweep.py` (every
rank runs it). The variants are dealt round-robin over the ranks; each rank runs whole variants in
its own process, on the whole mesh (its Soft Body filters see one process, not the ranks, and
read every piece), rank 0 runs the reference and sends its frames to the others, and rank 0
gathers the rows and writes the table and the plot: nothing but `output_dir` on rank 0 is
written, so no shared file system is needed. Every rank returns the whole table. The table is
the serial one except for the wall times (and so possibly the Pareto column).
"""

import csv
import itertools
import math
import os
import pickle
import time

from paraview import servermanager
from paraview.simple import Delete
from vtkmodules.util import numpy_support
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand, vtkOutputWindow, vtkUnsignedCharArray
from vtkmodules.vtkParallelCore import vtkDummyController, vtkMultiProcessController

DEFAULT_REFERENCE_TOLERANCE = 1e-5  # of the body's size, per simulated second


class SweepError(ValueError):
    """A grid the sweep cannot run (an unknown property or value)."""


def _validate(proxy, grid):
    names = proxy.ListProperties()
    for name, values in grid.items():
        if name not in names:
            raise SweepError(f"the Soft Body filter has no property {name!r}; valid: {', '.join(sorted(names))}")
        if not isinstance(values, (list, tuple)) or len(values) == 0:
            raise SweepError(f"grid[{name!r}] must be a non-empty list of values, got {values!r}")
        choices = getattr(proxy.GetProperty(name), "Available", None)
        if choices:
            for value in values:
                if isinstance(value, str) and value not in choices:
                    raise SweepError(f"{name} has no value {value!r}; valid: {', '.join(choices)}")


def _frames(end_time, frame_interval):
    count = max(1, int(round(end_time / frame_interval)))
    return [frame_interval * k for k in range(1, count + 1)]


class _Ranks:
    """The processes of `mpirun -np N pvbatch --symmetric` (every rank runs the script), or one.

    Under MPI a variant runs in this rank's process alone: its Soft Body is updated through its
    local VTK object with a one-process controller in place of the ranks' (the filter would
    otherwise distribute bodies over the ranks, and the reader give this rank only its piece).
    Objects travel as pickled bytes, rank 0 to and from each other rank."""

    _TAG = 7311

    def __init__(self):
        self.controller = vtkMultiProcessController.GetGlobalController()
        self.size = self.controller.GetNumberOfProcesses() if self.controller else 1
        self.rank = self.controller.GetLocalProcessId() if self.controller else 0
        self.local = self.size > 1
        self._alone = vtkDummyController() if self.local else None

    def mine(self, index):
        return index % self.size == self.rank

    def update(self, proxy, time):
        """Brings `proxy` to `time` in this process; returns its Mesh output's points or None."""
        if not self.local:
            proxy.UpdatePipeline(time)
            data = servermanager.Fetch(proxy)
        else:
            proxy.UpdateVTKObjects()
            vtkMultiProcessController.SetGlobalController(self._alone)
            try:
                algorithm = proxy.GetClientSideObject()
                algorithm.UpdateTimeStep(time)
                data = algorithm.GetOutputDataObject(0)
            finally:
                vtkMultiProcessController.SetGlobalController(self.controller)
        if data is None or data.GetNumberOfPoints() == 0:
            return None
        return numpy_support.vtk_to_numpy(data.GetPoints().GetData()).copy()

    def _send(self, value, rank):
        import numpy as np
        array = numpy_support.numpy_to_vtk(np.frombuffer(pickle.dumps(value), dtype=np.uint8), deep=True,
                                           array_type=vtkUnsignedCharArray().GetDataType())
        self.controller.Send(array, rank, self._TAG)

    def _receive(self, rank):
        array = vtkUnsignedCharArray()
        self.controller.Receive(array, rank, self._TAG)
        return pickle.loads(numpy_support.vtk_to_numpy(array).tobytes())

    def from_first(self, value):
        """Rank 0's `value`, on every rank."""
        if not self.local:
            return value
        if self.rank == 0:
            for other in range(1, self.size):
                self._send(value, other)
            return value
        return self._receive(0)

    def gathered(self, items):
        """Every rank's list of items, joined in rank order, on every rank."""
        if not self.local:
            return items
        if self.rank != 0:
            self._send(items, 0)
            return self.from_first(None)
        joined = list(items)
        for other in range(1, self.size):
            joined += self._receive(other)
        return self.from_first(joined)


class _FilterErrors:
    """The Soft Body filter's error messages while a variant runs (vtkOutputWindow's ErrorEvent),
    so that a failed variant's row says why."""

    def __init__(self):
        self.messages = []

        @calldata_type(VTK_STRING)
        def on_error(_obj, _event, text):
            if "vtkSoftBodyFilter" in text:
                self.messages.append(text.split("): ", 1)[-1].strip())

        self._callback = on_error  # the observer keeps only a weak link
        self._window = vtkOutputWindow.GetInstance()
        self._tag = self._window.AddObserver(vtkCommand.ErrorEvent, on_error)

    def first(self):
        return self.messages[0].splitlines()[0] if self.messages else "no message"

    def close(self):
        self._window.RemoveObserver(self._tag)


def _run_variant(ranks, make_body, values, end_time, frame_interval):
    """Runs one variant; returns (status, setup seconds, run seconds, positions per frame)."""
    proxy = make_body()
    errors = _FilterErrors()
    try:
        for name, value in values.items():
            setattr(proxy, name, value)
        proxy.EndTime = end_time
        proxy.FrameInterval = frame_interval
        start = time.perf_counter()
        x = ranks.update(proxy, 0.0)
        setup = time.perf_counter() - start
        if x is None:
            return f"failed at t = 0: {errors.first()}", setup, math.nan, None
        frames = []
        run = 0.0
        for t in _frames(end_time, frame_interval):
            start = time.perf_counter()
            x = ranks.update(proxy, t)
            run += time.perf_counter() - start
            if x is None:
                return f"failed at t = {t:g} s: {errors.first()}", setup, run, None
            frames.append(x)
        return "ok", setup, run, frames
    finally:
        errors.close()
        Delete(proxy)


def _error(frames, reference):
    import numpy as np
    worst = 0.0
    for x, r in zip(frames, reference):
        if x.shape != r.shape:
            return math.nan
        worst = max(worst, float(np.max(np.linalg.norm(x - r, axis=1))))
    return worst


def _label(values):
    return ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in values.items())


def pareto_front(rows):
    """The rows no other row beats in both run time and error (both lower or equal, one lower)."""
    ok = [r for r in rows if r["status"] == "ok" and math.isfinite(r["error"])]
    return [r for r in ok if not any(o["run_s"] <= r["run_s"] and o["error"] <= r["error"] and
                                     (o["run_s"] < r["run_s"] or o["error"] < r["error"]) for o in ok)]


def _plot(rows, front, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 5))
    for r in rows:
        if r["status"] == "ok" and r["error"] > 0.0:
            ax.scatter(r["run_s"], r["error"], color="tab:blue")
            ax.annotate(r["label"], (r["run_s"], r["error"]), fontsize=7, xytext=(3, 3), textcoords="offset points")
    front = sorted((r for r in front if r["error"] > 0.0), key=lambda r: r["run_s"])
    if front:
        ax.plot([r["run_s"] for r in front], [r["error"] for r in front], color="tab:red", label="Pareto front")
        ax.legend()
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("run time [s] (wall, after set-up)")
    ax.set_ylabel("error against the reference [m]")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def run(make_body, grid, end_time, frame_interval=None, reference=None, output_dir="softbody_sweep",
        progress=True):
    """Runs every combination of `grid` (property name -> list of values) on a new Soft Body from
    `make_body()`, and the reference; writes sweep.csv and sweep.png into output_dir and returns
    the rows (dicts: the grid's values, label, status, setup_s, run_s, error). Under
    `mpirun -np N pvbatch --symmetric` the variants are spread over the ranks (module docstring)."""
    if not callable(make_body):
        raise SweepError("make_body must be a function returning a new Soft Body proxy of the scene")
    if not (end_time > 0.0):
        raise SweepError(f"end_time must be > 0 s, got {end_time!r}")
    frame_interval = frame_interval or end_time / 10.0
    if not (0.0 < frame_interval <= end_time):
        raise SweepError(f"frame_interval must be in (0, end_time], got {frame_interval!r}")
    ranks = _Ranks()
    probe = make_body()
    try:
        _validate(probe, grid)
        if reference is None:
            x = ranks.update(probe, 0.0)
            if x is None:
                raise SweepError("the scene gives no output at t = 0 (see the error above)")
            size = float((x.max(axis=0) - x.min(axis=0)).max())
            # Newton solved tightly too: its residual would otherwise limit the reference.
            reference = {"Integrator": "BDF2", "TimeStepMode": "Error-controlled",
                         "ErrorTolerance": DEFAULT_REFERENCE_TOLERANCE * size, "ImplicitTolerance": 1e-8}
        _validate(probe, {name: [value] for name, value in reference.items()})
    finally:
        Delete(probe)
    if ranks.rank == 0:
        os.makedirs(output_dir, exist_ok=True)
    names = list(grid)
    variants = [dict(zip(names, combination)) for combination in itertools.product(*(grid[n] for n in names))]
    speaks = progress and ranks.rank == 0
    if speaks:
        over = f" over {ranks.size} ranks" if ranks.local else ""
        print(f"sweep: the reference ({reference}) and {len(variants)} variants{over}, {end_time:g} s each")
    # The reference is task 0 of the round robin: under MPI it runs beside the others' variants,
    # which keep their frames until it is known.
    tasks = [reference] + variants
    runs = {}
    expected = None
    for index, values in enumerate(tasks):
        if not ranks.mine(index):
            continue
        runs[index] = _run_variant(ranks, make_body, values, end_time, frame_interval)
        status, setup, run_s, frames = runs[index]
        if index == 0:
            if status != "ok" and not ranks.local:
                raise SweepError(f"the reference run {reference} {status}")
            expected = frames
        elif progress:
            where = f" (rank {ranks.rank})" if ranks.local else ""
            error = f", error {_error(frames, expected):.3g} m" if expected is not None and frames is not None else ""
            print(f"sweep: {index}/{len(variants)}{where} {_label(values)}: {status}, set-up {setup:.3g} s, "
                  f"run {run_s:.3g} s{error}", flush=True)
    status, _, reference_run, expected = ranks.from_first(runs.get(0))
    if status != "ok":
        raise SweepError(f"the reference run {reference} {status}")
    rows = []
    for index, (status, setup, run_s, frames) in runs.items():
        if index == 0:
            continue
        values = tasks[index]
        error = _error(frames, expected) if frames is not None else math.nan
        if status == "ok" and not math.isfinite(error):
            status = "ok, but its points are not the reference's (another count): no error measured"
        rows.append(dict(values, index=index, label=_label(values), status=status, setup_s=setup, run_s=run_s,
                         error=error))
    rows = sorted(ranks.gathered(rows), key=lambda r: r["index"])
    for r in rows:
        del r["index"]
    if ranks.rank != 0:
        return rows
    front = pareto_front(rows)
    with open(os.path.join(output_dir, "sweep.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(names + ["status", "setup_s", "run_s", "error_m", "pareto"])
        for r in rows:
            writer.writerow([r[n] for n in names] + [r["status"], f"{r['setup_s']:.6g}", f"{r['run_s']:.6g}",
                                                     f"{r['error']:.6g}", int(r in front)])
    _plot(rows, front, os.path.join(output_dir, "sweep.png"))
    if speaks:
        print(f"sweep: wrote {output_dir}/sweep.csv and sweep.png (reference run {reference_run:.3g} s)")
    return rows
