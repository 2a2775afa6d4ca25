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
"""

import csv
import itertools
import math
import os
import time

from paraview import servermanager
from paraview.simple import Delete
from vtkmodules.util import numpy_support
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand, vtkOutputWindow

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


def _positions(proxy):
    data = servermanager.Fetch(proxy)
    if data is None or data.GetNumberOfPoints() == 0:
        return None
    return numpy_support.vtk_to_numpy(data.GetPoints().GetData()).copy()


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


def _run_variant(make_body, values, end_time, frame_interval):
    """Runs one variant; returns (status, setup seconds, run seconds, positions per frame)."""
    proxy = make_body()
    errors = _FilterErrors()
    try:
        for name, value in values.items():
            setattr(proxy, name, value)
        proxy.EndTime = end_time
        proxy.FrameInterval = frame_interval
        start = time.perf_counter()
        proxy.UpdatePipeline(0.0)
        setup = time.perf_counter() - start
        if _positions(proxy) is None:
            return f"failed at t = 0: {errors.first()}", setup, math.nan, None
        frames = []
        run = 0.0
        for t in _frames(end_time, frame_interval):
            start = time.perf_counter()
            proxy.UpdatePipeline(t)
            run += time.perf_counter() - start
            x = _positions(proxy)
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
    the rows (dicts: the grid's values, label, status, setup_s, run_s, error)."""
    if not callable(make_body):
        raise SweepError("make_body must be a function returning a new Soft Body proxy of the scene")
    if not (end_time > 0.0):
        raise SweepError(f"end_time must be > 0 s, got {end_time!r}")
    frame_interval = frame_interval or end_time / 10.0
    if not (0.0 < frame_interval <= end_time):
        raise SweepError(f"frame_interval must be in (0, end_time], got {frame_interval!r}")
    probe = make_body()
    try:
        _validate(probe, grid)
        if reference is None:
            probe.UpdatePipeline(0.0)
            x = _positions(probe)
            if x is None:
                raise SweepError("the scene gives no output at t = 0 (see the error above)")
            size = float((x.max(axis=0) - x.min(axis=0)).max())
            # Newton solved tightly too: its residual would otherwise limit the reference.
            reference = {"Integrator": "BDF2", "TimeStepMode": "Error-controlled",
                         "ErrorTolerance": DEFAULT_REFERENCE_TOLERANCE * size, "ImplicitTolerance": 1e-8}
        _validate(probe, {name: [value] for name, value in reference.items()})
    finally:
        Delete(probe)
    os.makedirs(output_dir, exist_ok=True)
    names = list(grid)
    variants = [dict(zip(names, combination)) for combination in itertools.product(*(grid[n] for n in names))]
    if progress:
        print(f"sweep: the reference ({reference}) and {len(variants)} variants, {end_time:g} s each")
    status, _, reference_run, expected = _run_variant(make_body, reference, end_time, frame_interval)
    if status != "ok":
        raise SweepError(f"the reference run {reference} {status}")
    rows = []
    for index, values in enumerate(variants, 1):
        status, setup, run_s, frames = _run_variant(make_body, values, end_time, frame_interval)
        error = _error(frames, expected) if frames is not None else math.nan
        if status == "ok" and not math.isfinite(error):
            status = "ok, but its points are not the reference's (another count): no error measured"
        label = ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in values.items())
        rows.append(dict(values, label=label, status=status, setup_s=setup, run_s=run_s, error=error))
        if progress:
            print(f"sweep: {index}/{len(variants)} {label}: {status}, set-up {setup:.3g} s, "
                  f"run {run_s:.3g} s, error {error:.3g} m", flush=True)
    front = pareto_front(rows)
    with open(os.path.join(output_dir, "sweep.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(names + ["status", "setup_s", "run_s", "error_m", "pareto"])
        for r in rows:
            writer.writerow([r[n] for n in names] + [r["status"], f"{r['setup_s']:.6g}", f"{r['run_s']:.6g}",
                                                     f"{r['error']:.6g}", int(r in front)])
    _plot(rows, front, os.path.join(output_dir, "sweep.png"))
    if progress:
        print(f"sweep: wrote {output_dir}/sweep.csv and sweep.png (reference run {reference_run:.3g} s)")
    return rows
