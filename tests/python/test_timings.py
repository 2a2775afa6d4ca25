"""python.timings: the Timings port and field data say where a run's wall time went.

The jelly is simulated to 0.4 s in frames of 0.04 s, under Euler-Cromer, Implicit Euler and
XPBD. The Timings table then has a row per simulated frame: Time on the frame grid, a column per stage of the Plan (the Mesh's Plan labels),
Other and Total; no stage is negative, Other is what the frame took outside the stages and is
not negative either (a stage timed twice would make it so), and each
stage's column sums to its StageSeconds (the accumulated time the Mesh reports). SetupSeconds is
positive and SimulationSeconds is the sum of Total. Replayed from the cache at 0.2 s the table
shows the first five rows unchanged (a cached frame keeps its record); a property that rebuilds
the run starts a new record. The README's pvpython example reads these the same way.
"""
import os

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from vtkmodules.util import numpy_support

import softbody_testing as sbt

TIMINGS_PORT = 5
args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())
jelly = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
body = SoftBody(Input=jelly, EndTime=0.4, FrameInterval=0.04)


def table_at(t):
    table = sbt.output_at(body, t, TIMINGS_PORT)
    columns = {table.GetColumnName(c): numpy_support.vtk_to_numpy(table.GetColumn(c)).copy()
               for c in range(table.GetNumberOfColumns())}
    return table, columns


# Each method's stepper times its own stages; a stage timed twice would make Other negative.
for label, properties in (("Mass-Spring, Euler-Cromer", {}), ("Mass-Spring, Implicit Euler", {"Integrator": "Implicit Euler"}),
                          ("XPBD", {"Method": "XPBD"})):
    check_body = SoftBody(Input=jelly, EndTime=0.4, FrameInterval=0.04, **properties)
    mesh = sbt.output_at(check_body, 0.4)
    table = sbt.output_at(check_body, 0.4, TIMINGS_PORT)
    columns = {table.GetColumnName(c): numpy_support.vtk_to_numpy(table.GetColumn(c)).copy()
               for c in range(table.GetNumberOfColumns())}
    plan = mesh.GetFieldData().GetAbstractArray("Plan")
    labels = [plan.GetValue(i) for i in range(plan.GetNumberOfValues())]
    stage_seconds = numpy_support.vtk_to_numpy(mesh.GetFieldData().GetArray("StageSeconds"))
    print(f"{label}: columns {list(columns)}")
    for row in range(table.GetNumberOfRows()):
        print("  " + "  ".join(f"{name[:12]}={values[row]:.2e}" for name, values in columns.items()))
    sbt.check(list(columns) == ["Time"] + labels + ["Other", "Total"],
              f"{label}: columns Time, the Plan's stages in order, Other, Total")
    sbt.check(np.allclose(columns["Time"], 0.04 * np.arange(1, 11), rtol=0, atol=1e-12),
              f"{label}: a row per simulated frame, 0.04 s to 0.4 s")
    stages = np.array([columns[name] for name in labels])
    sbt.check(np.all(stages >= 0.0) and np.all(columns["Other"] >= 0.0),
              f"{label}: no stage and no remainder is negative (no stage is timed twice)")
    sbt.check(np.allclose(stages.sum(axis=0) + columns["Other"], columns["Total"], rtol=1e-12, atol=1e-15),
              f"{label}: each row's stages and Other add up to its Total")
    sbt.check(np.allclose(stages.sum(axis=1), stage_seconds, rtol=1e-9, atol=1e-12),
              f"{label}: each stage's column sums to the StageSeconds the Mesh reports")
    Delete(check_body)

mesh = sbt.output_at(body, 0.4)
table, columns = table_at(0.4)
setup = sbt.field_value(mesh, "SetupSeconds")
simulated = sbt.field_value(mesh, "SimulationSeconds")
print(f"SetupSeconds {setup:.4f} s, SimulationSeconds {simulated:.4f} s")
sbt.check(setup > 0.0, "the set-up took time")
sbt.check(np.isclose(simulated, columns["Total"].sum(), rtol=1e-12), "SimulationSeconds is the frames' total")
sbt.check(sbt.field_value(table, "SetupSeconds") == setup, "the table carries SetupSeconds too")

_, replayed = table_at(0.2)
sbt.check(all(np.array_equal(replayed[name], values[:5]) for name, values in columns.items()),
          "replayed from the cache at 0.2 s: the first five rows, unchanged")

body.YoungsModulus = 2.0e5
_, rebuilt = table_at(0.08)
sbt.check(len(rebuilt["Time"]) == 2 and not np.array_equal(rebuilt["Total"], columns["Total"][:2]),
          "a rebuilt run starts a new record")
print("python.timings: all checks passed")
