"""python.sweep: `from softbody import sweep` on a user's mesh, as a pvpython user runs it.

A bar hanging from its pinned top (written here, as a user's .vtu) swept over Integrator x
TimeStep against the default reference (BDF2, error-controlled): the CSV has a row per variant
with its set-up and run times and its error, BDF2's error falls at about its second order when
the step is divided by 4 (Implicit Euler's at about its first), the Pareto front is marked and
the plot written; an explicit variant far above its stable step blows up and is recorded as
failed while the sweep goes on; an unknown property and an unknown value are refused naming
them and listing the valid ones. The same sweep under `mpirun -np 2 pvbatch --symmetric` (this
script, --ranks) writes the same table except for the wall times and the Pareto column, with
variants run on both ranks; the wall time of the whole sweep at 1 and 2 ranks is printed."""

import csv
import json
import math
import os
import shutil
import sys
import tempfile
import time

from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt



def extra_args(parser):
    parser.add_argument("--ranks", action="store_true", help="the pvbatch side (internal)")
    parser.add_argument("--input", help="the bar's .vtu (internal)")
    parser.add_argument("--out", help="where the pvbatch side writes its sweep (internal)")


args = sbt.parse_args(__doc__, extra_args)
LoadPlugin(args.plugin, remote=False, ns=globals())
from softbody import sweep  # noqa: E402  (embedded in the plugin: importable once it is loaded)

GRID = {"Integrator": ["BDF2", "Implicit Euler", "Euler-Cromer"], "TimeStep": [0.002, 0.0005]}


def run_sweep(bar_path, out):
    """The sweep of this test on the bar in `bar_path`; returns its wall time [s] and the scene."""
    bar = XMLUnstructuredGridReader(FileName=[bar_path])

    def scene():
        return SoftBody(Input=bar, PinnedPointsArray="Pinned", Floor=0, ImplicitTolerance=1e-8)

    start = time.perf_counter()
    sweep.run(scene, grid=GRID, end_time=0.2, frame_interval=0.05, output_dir=out)
    return time.perf_counter() - start, scene


def ranks_side():
    """The pvbatch side: every rank runs this; rank 0 writes the table and its wall time."""
    from vtkmodules.vtkParallelCore import vtkMultiProcessController
    controller = vtkMultiProcessController.GetGlobalController()
    seconds, _ = run_sweep(args.input, args.out)
    if controller.GetLocalProcessId() == 0:
        with open(os.path.join(args.out, "run.json"), "w") as info:
            json.dump({"ranks": controller.GetNumberOfProcesses(), "seconds": seconds}, info)


def serial_side():
    """The checks, in pvpython: the sweep here, then the same over two ranks."""
    workdir = tempfile.mkdtemp(prefix="softbody_sweep_")
    path, rest = sbt.write_tet_box(workdir, 2, 2, 6, 0.02, pinned=lambda p: p[2] > 0.12 - 1e-9)
    out = os.path.join(workdir, "out")
    serial_seconds, scene = run_sweep(path, out)
    with open(os.path.join(out, "sweep.csv")) as f:
        table = list(csv.DictReader(f))
    sbt.check(len(table) == 6, f"a row per variant ({len(table)})")
    sbt.check(os.path.getsize(os.path.join(out, "sweep.png")) > 0, "the plot is written")
    by = {(r["Integrator"], float(r["TimeStep"])): r for r in table}
    for integrator, order in (("BDF2", 2), ("Implicit Euler", 1)):
        coarse, fine = float(by[(integrator, 0.002)]["error_m"]), float(by[(integrator, 0.0005)]["error_m"])
        measured = math.log(coarse / fine) / math.log(4.0)
        print(f"{integrator}: error {coarse:.3g} -> {fine:.3g} m, order {measured:.2f}")
        sbt.check(abs(measured - order) < 0.6, f"{integrator}: error falls at about order {order} ({measured:.2f})")
        for step in (0.002, 0.0005):
            r = by[(integrator, step)]
            sbt.check(r["status"] == "ok" and float(r["setup_s"]) > 0 and float(r["run_s"]) > 0,
                      f"{integrator} at {step}: timed ({r['setup_s']} s set-up, {r['run_s']} s run)")
    blown = by[("Euler-Cromer", 0.002)]
    sbt.check(blown["status"].startswith("failed") and "blew up" in blown["status"],
              f"Euler-Cromer far above its stable step fails, saying why ({blown['status']!r})")
    sbt.check(any(r["pareto"] == "1" for r in table), "the Pareto front is marked")

    for grid, words in (({"TimeStepp": [0.01]}, ["TimeStepp", "TimeStep", "Integrator"]),
                        ({"Integrator": ["BDF3"]}, ["BDF3", "BDF2", "Implicit Euler"])):
        try:
            sweep.run(scene, grid=grid, end_time=0.1, output_dir=out, progress=False)
            sbt.check(False, f"{grid}: refused")
        except sweep.SweepError as e:
            sbt.check(all(w in str(e) for w in words), f"{grid}: refused naming {words} ({str(e)[:120]!r})")

    # The same sweep over two MPI ranks.
    mpirun, pvbatch = shutil.which("mpirun"), shutil.which("pvbatch")
    if not mpirun or not pvbatch:
        print(f"SKIP: mpirun ({mpirun}) or pvbatch ({pvbatch}) not found")
        sys.exit(sbt.SKIP)
    ranks_out = os.path.join(workdir, "ranks")
    os.makedirs(ranks_out)
    command = [mpirun, "-np", "2", pvbatch, "--symmetric", os.path.abspath(__file__), "--ranks",
               "--plugin", args.plugin, "--input", path, "--out", ranks_out]
    output = sbt.run_under_mpirun(command, timeout=300)
    with open(os.path.join(ranks_out, "run.json")) as info_file:
        info = json.load(info_file)
    sbt.check(info["ranks"] == 2, f"the pvbatch side ran on 2 ranks (got {info['ranks']})")
    sbt.check("(rank 0)" in output and "(rank 1)" in output, "both ranks ran variants")
    with open(os.path.join(ranks_out, "sweep.csv")) as f:
        ranked = list(csv.DictReader(f))
    sbt.check(len(ranked) == len(table), f"the ranks' table has a row per variant ({len(ranked)})")
    same = ("Integrator", "TimeStep", "status", "error_m")
    for serial_row, ranks_row in zip(table, ranked):
        sbt.check(all(serial_row[k] == ranks_row[k] for k in same),
                  f"{serial_row['Integrator']} at {serial_row['TimeStep']}: the ranks' row is the serial one "
                  f"({ranks_row['status'][:40]}, error {ranks_row['error_m']} m)")
    sbt.check(os.path.getsize(os.path.join(ranks_out, "sweep.png")) > 0, "rank 0 writes the plot")
    print(f"sweep wall time: {serial_seconds:.2f} s serial, {info['seconds']:.2f} s over 2 ranks "
          f"(speed-up {serial_seconds / info['seconds']:.2f})")
    print("python.sweep: all checks passed")


# pvbatch must leave its script normally (a sys.exit skips MPI's finalize on that rank).
if args.ranks:
    ranks_side()
else:
    serial_side()
