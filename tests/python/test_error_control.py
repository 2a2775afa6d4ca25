"""python.error_control: error-controlled steps and BDF2 through the filter, as a pvpython user
runs them.

A bar hanging from its pinned top face, released from rest, run with TimeStepMode
Error-controlled at two tolerances a decade apart and against a BDF2 reference at a fixed step
far below the controller's: the error of each frame is within the tolerance, the tighter
tolerance takes more steps and lands closer, and the field data reports what the controller
did (AcceptedSteps, RejectedSteps, EstimatedError, SmallestStep, LargestStep); the first frame's
whole-interval step is rejected and said to be. An explicit integrator (Verlet) under error
control never steps above its stable step. XPBD under error control lands within the
tolerance of an XPBD run at a fixed step far below its steps, and reports the same fields."""

import tempfile

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())
workdir = tempfile.mkdtemp(prefix="softbody_error_control_")

CELL, LENGTH = 0.02, 10
path, rest = sbt.write_tet_box(workdir, 2, 2, LENGTH, CELL, pinned=lambda p: p[2] > LENGTH * CELL - 1e-9)
bar = XMLUnstructuredGridReader(FileName=[path])
END, FRAME = 0.2, 0.05
common = dict(Input=bar, PinnedPointsArray="Pinned", Floor=0, DampingTime=0.0, EndTime=END,
              FrameInterval=FRAME, ImplicitTolerance=1e-10, ImplicitMaxIterations=100)

reference = SoftBody(Integrator="BDF2", TimeStep=2e-5, **common)
times = [FRAME * k for k in range(1, round(END / FRAME) + 1)]
expected = {t: sbt.points_of(sbt.output_at(reference, t)) for t in times}

steps = {}
errors = {}
for tolerance in (1e-3, 1e-4):
    body = SoftBody(Integrator="BDF2", TimeStepMode="Error-controlled", ErrorTolerance=tolerance, **common)
    worst = 0.0
    total = 0
    for k, t in enumerate(times):
        mesh = sbt.output_at(body, t)
        worst = max(worst, float(np.max(np.linalg.norm(sbt.points_of(mesh) - expected[t], axis=1))))
        accepted = sbt.field_value(mesh, "AcceptedSteps")
        rejected = sbt.field_value(mesh, "RejectedSteps")
        estimate = sbt.field_value(mesh, "EstimatedError")
        smallest, largest = sbt.field_value(mesh, "SmallestStep"), sbt.field_value(mesh, "LargestStep")
        sbt.check(accepted is not None and accepted > 0, f"{tolerance}: AcceptedSteps reported at t = {t}")
        sbt.check(estimate is not None and 0.0 <= estimate < tolerance * FRAME,
                  f"{tolerance}: EstimatedError {estimate} within the frame's share of the tolerance")
        sbt.check(0.0 < smallest <= largest <= FRAME, f"{tolerance}: step range [{smallest}, {largest}] s")
        if k == 0:
            sbt.check(rejected > 0, f"{tolerance}: the first frame's whole-interval step is rejected ({rejected})")
        total += accepted
    print(f"BDF2 at {tolerance} m/s: worst error {worst:.3g} m, {total} accepted steps")
    sbt.check(worst < tolerance, f"{tolerance}: error {worst:.3g} m within the tolerance")
    steps[tolerance], errors[tolerance] = total, worst
sbt.check(steps[1e-4] > steps[1e-3] and errors[1e-4] < errors[1e-3],
          f"the tighter tolerance takes more steps ({steps}) and lands closer ({errors})")

verlet = SoftBody(Integrator="Verlet", TimeStepMode="Error-controlled", ErrorTolerance=1e-4, **common)
mesh = sbt.output_at(verlet, FRAME)
stable = sbt.field_value(mesh, "StableTimeStep")
largest = sbt.field_value(mesh, "LargestStep")
sbt.check(0.0 < largest <= stable, f"Verlet: largest step {largest} s within the stable step {stable} s")

# XPBD: its steps are first order, so the tolerance is met against XPBD itself at a fine step.
xpbd_common = dict(Input=bar, PinnedPointsArray="Pinned", Floor=0, EndTime=FRAME, FrameInterval=FRAME,
                   Method="XPBD", Iterations=20)
xpbd_reference = sbt.points_of(sbt.output_at(SoftBody(TimeStep=2e-5, **xpbd_common), FRAME))
tolerance = 1e-3
mesh = sbt.output_at(SoftBody(TimeStepMode="Error-controlled", ErrorTolerance=tolerance, **xpbd_common), FRAME)
error = float(np.max(np.linalg.norm(sbt.points_of(mesh) - xpbd_reference, axis=1)))
accepted = sbt.field_value(mesh, "AcceptedSteps")
print(f"XPBD at {tolerance} m/s: error {error:.3g} m in {accepted} steps over {FRAME} s")
sbt.check(accepted is not None and accepted > 1, f"XPBD: AcceptedSteps {accepted} reported")
sbt.check(sbt.field_value(mesh, "SimulationTime") == FRAME, "XPBD: the steps end on the frame time")
sbt.check(error < tolerance * FRAME, f"XPBD: error {error:.3g} m within the tolerance's share of the frame")
print("python.error_control: all checks passed")
