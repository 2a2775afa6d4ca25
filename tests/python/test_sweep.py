"""python.sweep: `from softbody import sweep` on a user's mesh, as a pvpython user runs it.

A bar hanging from its pinned top (written here, as a user's .vtu) swept over Integrator x
TimeStep against the default reference (BDF2, error-controlled): the CSV has a row per variant
with its set-up and run times and its error, BDF2's error falls at about its second order when
the step is divided by 4 (Implicit Euler's at about its first), the Pareto front is marked and
the plot written; an explicit variant far above its stable step blows up and is recorded as
failed while the sweep goes on; an unknown property and an unknown value are refused naming
them and listing the valid ones."""

import csv
import math
import os
import tempfile

from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())
from softbody import sweep  # noqa: E402  (embedded in the plugin: importable once it is loaded)

workdir = tempfile.mkdtemp(prefix="softbody_sweep_")
path, rest = sbt.write_tet_box(workdir, 2, 2, 6, 0.02, pinned=lambda p: p[2] > 0.12 - 1e-9)
bar = XMLUnstructuredGridReader(FileName=[path])


def scene():
    return SoftBody(Input=bar, PinnedPointsArray="Pinned", Floor=0, ImplicitTolerance=1e-8)


out = os.path.join(workdir, "out")
rows = sweep.run(scene, grid={"Integrator": ["BDF2", "Implicit Euler", "Euler-Cromer"],
                              "TimeStep": [0.002, 0.0005]},
                 end_time=0.2, frame_interval=0.05, output_dir=out)
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
print("python.sweep: all checks passed")
