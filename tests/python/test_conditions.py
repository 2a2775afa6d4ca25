"""python.conditions: loads and boundary conditions through Soft Body Condition, as a pvpython
user applies them.

1. A bar fixed at x = 0 (a half-space region) and pulled by a force F spread by area over its
   end face (a box region), Static, Corotated with nu = 0: it stretches by F L / (E A) to 1e-6,
   the Reaction point array sums to -F and the field data "support Force" is -F, "end load
   Force" is F. Under XPBD with Stable Neo-Hookean the same bar, damped to rest, stretches and
   reacts the same within 1 %; under PBD (no forces of the state: the reaction is the momentum
   its projections gave the support) it reacts -F within 1 %.
2. The patch test on a TetGen cube with rollers: each face holds its normal component, the
   faces x = 1 and y = 1 moved along their normals (Prescribed Motion, that component only).
   The exact answer is the homogeneous stretch diag(1.1, 0.95, 1); every interior point lands on
   it for the finite-element models (the spring network's error printed).
3. Prescribed Motion with keyframes moves its set exactly where the keys put it at every frame.
4. Pressure p on the whole surface of the bundled jelly (TetGen) inflates it by p / K with no
   net force.
   Prescribed Motion and keyframes hold under Mass-Spring, XPBD and PBD alike.
5. Bad conditions: a set from another mesh, a pressure on a set with no boundary face, an empty
   region, each with a message naming the condition.
6. The initial state: a spin about the centre of mass has the rigid rotation's kinetic energy,
   and a run restarted from a saved frame's Displacement and Velocity continues it.
7. A condition changed during playback (a Pull handle moved): earlier frames stay, the change
   applies from the frame shown on, and the run replays the same from frame 0."""

import builtins
import os
import tempfile

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())
workdir = tempfile.mkdtemp(prefix="softbody_conditions_")
sbt.check("SoftBodyCondition" in globals(), "LoadPlugin defines SoftBodyCondition()")

# 1. The bar.
E, FORCE, CELL = 1.0e5, 0.1, 0.01
LENGTH, SIDE = 10 * CELL, 2 * CELL
path, rest = sbt.write_tet_box(workdir, 10, 2, 2, CELL)
bar = XMLUnstructuredGridReader(FileName=[path])
support = SoftBodyCondition(Input=bar, ConditionName="support", ConditionType="Fixed",
                            Region="Half-space", PlaneOrigin=[0, 0, 0], PlaneNormal=[-1, 0, 0])
load = SoftBodyCondition(Input=bar, ConditionName="end load", ConditionType="Force",
                         Region="Box", BoxPosition=[LENGTH - 1e-6, -1, -1], BoxScale=[1, 3, 3],
                         Force=[FORCE, 0, 0], ForceSpread="Total, by area")
body = SoftBody(Input=bar, Conditions=[support, load], MaterialModel="Corotated", Integrator="Static",
                YoungsModulus=E, PoissonRatio=0.0, Gravity=[0, 0, 0], Floor=0, EndTime=0.1,
                FrameInterval=0.1, ImplicitTolerance=1e-10)
mesh = sbt.output_at(body, 0.1)
x = sbt.points_of(mesh)
end = rest[:, 0] > LENGTH - 1e-9
elongation = float(np.mean(x[end, 0] - rest[end, 0]))
expected = FORCE * LENGTH / (E * SIDE * SIDE)
print(f"bar: elongation {elongation:.6e} m, F L / (E A) = {expected:.6e} m")
sbt.check(abs(elongation / expected - 1) < 1e-6, "bar: elongation F L / (E A) to 1e-6")
reaction = sbt.point_array(mesh, "Reaction")
sbt.check(abs(reaction[:, 0].sum() + FORCE) < 1e-6 * FORCE, f"bar: Reaction sums to -F ({reaction[:, 0].sum():.9f} N)")
sbt.check(np.abs(reaction[rest[:, 0] > 1e-9]).max() == 0.0, "bar: free points have no reaction")
held = mesh.GetFieldData().GetArray("support Force")
applied = mesh.GetFieldData().GetArray("end load Force")
sbt.check(held is not None and abs(held.GetTuple3(0)[0] + FORCE) < 1e-6 * FORCE, "bar: field data 'support Force' is -F")
sbt.check(applied is not None and abs(applied.GetTuple3(0)[0] - FORCE) < 1e-12, "bar: field data 'end load Force' is F")
sbt.check(mesh.GetFieldData().GetArray("support Moment") is not None, "bar: field data 'support Moment'")
Delete(body)

# The same bar under XPBD with Stable Neo-Hookean, damped to rest: XPBD's constraints are the
# law's energy, so it stretches by F L / (E A) and the support's reaction is -F, up to XPBD's
# error, which falls with the square of the substep (methods.md): within 1 % on these 1 cm cells
# takes 32 substeps of 1/120 s.
body = SoftBody(Input=bar, Conditions=[support, load], Method="XPBD", MaterialModel="Stable Neo-Hookean",
                YoungsModulus=E, PoissonRatio=0.0, Gravity=[0, 0, 0], Floor=0, Substeps=32,
                VelocityDamping=5.0, EndTime=3.0, FrameInterval=3.0)
mesh = sbt.output_at(body, 3.0)
x = sbt.points_of(mesh)
elongation = float(np.mean(x[end, 0] - rest[end, 0]))
reaction = sbt.point_array(mesh, "Reaction")
held = mesh.GetFieldData().GetArray("support Force")
print(f"XPBD bar: elongation {elongation:.6e} m (F L / (E A) = {expected:.6e} m), Reaction sum {reaction[:, 0].sum():.6f} N")
sbt.check(abs(elongation / expected - 1) < 0.01, "XPBD bar: elongation F L / (E A) within 1 %")
sbt.check(abs(reaction[:, 0].sum() + FORCE) < 0.01 * FORCE, "XPBD bar: Reaction sums to -F within 1 %")
sbt.check(held is not None and abs(held.GetTuple3(0)[0] + FORCE) < 0.01 * FORCE, "XPBD bar: field data 'support Force' is -F")
Delete(body)

# The same bar under PBD (Solver Gauss-Seidel), damped to rest: its stiffnesses are no forces,
# but what its projections gave the held points is (methods.md), and at rest the support
# answers -F.
body = SoftBody(Input=bar, Conditions=[support, load], Method="PBD", Gravity=[0, 0, 0], Floor=0, Substeps=8,
                VelocityDamping=5.0, EndTime=3.0, FrameInterval=3.0)
mesh = sbt.output_at(body, 3.0)
reaction = sbt.point_array(mesh, "Reaction")
held = mesh.GetFieldData().GetArray("support Force")
print(f"PBD bar: Reaction sum {reaction[:, 0].sum():.6f} N against -F = {-FORCE} N")
sbt.check(abs(reaction[:, 0].sum() + FORCE) < 0.01 * FORCE, "PBD bar: Reaction sums to -F within 1 %")
sbt.check(held is not None and abs(held.GetTuple3(0)[0] - reaction[:, 0].sum()) < 1e-9 * FORCE,
          "PBD bar: field data 'support Force' is the sum of the Reaction array")
Delete(body)

# 2. The patch test with rollers on a TetGen cube.
cube = TetrahedralizeSurfaceTetGen(Input=Triangulate(Input=Box(Center=[0.5, 0.5, 0.5])),
                                   MaxTetVolume=0.002, MaxTetVolumeIsRelative=0)
cube.UpdatePipeline()
stretch = np.array([1.1, 0.95, 1.0])
rollers = []
for axis, name in enumerate("xyz"):
    for side in (0.0, 1.0):
        normal = [0.0, 0.0, 0.0]
        normal[axis] = 1.0 if side else -1.0
        origin = [0.0, 0.0, 0.0]
        origin[axis] = side
        held = [0, 0, 0]
        held[axis] = 1
        moved = side == 1.0 and stretch[axis] != 1.0
        translation = [0.0, 0.0, 0.0]
        translation[axis] = stretch[axis] - 1.0 if moved else 0.0
        rollers.append(SoftBodyCondition(
            Input=cube, ConditionName=f"{name}={side:g}", Region="Half-space", PlaneOrigin=origin,
            PlaneNormal=normal, HeldComponents=held,
            ConditionType="Prescribed Motion" if moved else "Fixed", Translation=translation))
for model in ("Corotated", "Stable Neo-Hookean", "Spring Network"):
    body = SoftBody(Input=cube, Conditions=rollers, MaterialModel=model, Integrator="Static",
                    YoungsModulus=1e5, PoissonRatio=0.3, Gravity=[0, 0, 0], Floor=0, EndTime=0.1,
                    FrameInterval=0.1, ImplicitTolerance=1e-10)
    mesh = sbt.output_at(body, 0.1)
    x = sbt.points_of(mesh)
    x0 = x - sbt.point_array(mesh, "Displacement")
    inside = (x0.min(axis=1) > 1e-9) & (x0.max(axis=1) < 1 - 1e-9)
    worst = float(np.abs(x[inside] - x0[inside] * stretch).max())
    print(f"patch test, {model}: {int(inside.sum())} interior points of {len(x)}, worst error {worst:.3e} m")
    if model != "Spring Network":
        sbt.check(inside.sum() > 10 and worst < 1e-8, f"patch test, {model}: the interior lands on the map")
    Delete(body)

# 3. Keyframed prescribed motion.
path, rest = sbt.write_tet_box(workdir, 3, 3, 3, 0.1)
box = XMLUnstructuredGridReader(FileName=[path])
keys = [0.0, 0.0, 0.1, 1.0, 0.25, 0.4]
drive = SoftBodyCondition(Input=box, ConditionName="drive", ConditionType="Prescribed Motion",
                          Region="Half-space", PlaneOrigin=[0, 0, 0], PlaneNormal=[0, 0, -1],
                          Translation=[0.05, -0.02, 0.01], Profile="Keyframes", Keyframes=keys)
bottom = rest[:, 2] < 1e-9
for method in ("Mass-Spring", "XPBD", "PBD"):
    model = "Corotated" if method == "Mass-Spring" else "Spring Network"
    body = SoftBody(Input=box, Conditions=[drive], Method=method, MaterialModel=model,
                    YoungsModulus=1e4, Floor=0, EndTime=0.3, FrameInterval=0.05)
    for t in (0.05, 0.1, 0.2, 0.3):
        x = sbt.points_of(sbt.output_at(body, t))
        s = float(np.interp(t, keys[0::2], keys[1::2]))
        worst = float(np.abs(x[bottom] - (rest[bottom] + s * np.array([0.05, -0.02, 0.01]))).max())
        sbt.check(worst < 1e-15, f"keyframes, {method}: at t = {t} the set is where the keys put it (worst {worst:.1e} m)")
    Delete(body)

# 4. Pressure inflates the jelly.
jelly = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
gas = SoftBodyCondition(Input=jelly, ConditionName="gas", ConditionType="Pressure",
                        Region="All points", Pressure=200.0)  # PRESSURE below
YOUNG, NU, PRESSURE = 1.0e5, 0.3, 200.0
body = SoftBody(Input=jelly, Conditions=[gas], MaterialModel="Stable Neo-Hookean",
                YoungsModulus=YOUNG, PoissonRatio=NU, Integrator="Implicit Euler",
                Gravity=[0, 0, 0], Floor=0, EndTime=1.0, FrameInterval=0.1)
start = sbt.output_at(body, 0.0)
mesh = sbt.output_at(body, 1.0)
ratios = sbt.cell_array(mesh, "VolumeRatio")
growth = float(ratios.mean()) - 1
force = mesh.GetFieldData().GetArray("gas Force").GetTuple3(0)
bulk = YOUNG / (3 * (1 - 2 * NU))
print(f"jelly: mean volume ratio grows by {growth:.4e} (p / K = {PRESSURE / bulk:.4e}); "
      f"net pressure force {np.linalg.norm(force):.2e} N")
sbt.check(abs(growth / (PRESSURE / bulk) - 1) < 0.03, "jelly: pressure inflates it by p / K (hydrostatic tension) within 3 %")
sbt.check(np.linalg.norm(force) < 1e-9, "jelly: the pressure on a closed surface has no net force")
Delete(body)

# 6. Initial state: a spin has the kinetic energy of the rigid rotation; a run restarted from a
#    saved frame's Displacement and Velocity continues it.
spin = SoftBody(Input=jelly, Gravity=[0, 0, 0], Floor=0, InitialVelocity=[0.1, 0, 0],
                InitialAngularVelocity=[0, 0, 2.0], EndTime=0.1, FrameInterval=0.05)
first = sbt.output_at(spin, 0.0)
x, v = sbt.points_of(first), sbt.point_array(first, "Velocity")
masses = sbt.point_array(sbt.output_at(spin, 0.0, port=1), "InverseMass")
m = 1.0 / masses
centre = (m[:, None] * x).sum(axis=0) / m.sum()
want = 0.5 * (m * np.sum((np.array([0.1, 0, 0]) + np.cross([0, 0, 2.0], x - centre)) ** 2, axis=1)).sum()
kinetic = sbt.field_value(first, "KineticEnergy")
sbt.check(abs(kinetic / want - 1) < 1e-12, f"initial spin: kinetic energy {kinetic:.6g} J is the rigid motion's")
sbt.check(np.abs((m[:, None] * v).sum(axis=0) - m.sum() * np.array([0.1, 0, 0])).max() < 1e-12,
          "initial spin: the momentum is the uniform velocity's only")
Delete(spin)
run = SoftBody(Input=jelly, EndTime=1.0, FrameInterval=0.1, TimeStep=1e-3)
half = sbt.output_at(run, 0.5)
whole = sbt.points_of(sbt.output_at(run, 1.0))
restart_input = PVTrivialProducer()
at_rest = half.NewInstance()
at_rest.DeepCopy(half)
from vtkmodules.util import numpy_support  # noqa: E402
at_rest.GetPoints().SetData(numpy_support.numpy_to_vtk(sbt.points_of(half) - sbt.point_array(half, "Displacement"), deep=True))
restart_input.GetClientSideObject().SetOutput(at_rest)
restart = SoftBody(Input=restart_input, InitialDisplacementArray="Displacement",
                   InitialVelocityArray="Velocity", EndTime=0.5, FrameInterval=0.1, TimeStep=1e-3)
again = sbt.points_of(sbt.output_at(restart, 0.5))
gap = float(np.abs(again - whole).max())
sbt.check(gap < 1e-9, f"restart: 0.5 s from the saved frame lands where the run did at 1 s (gap {gap:.1e} m)")
Delete(restart)
Delete(run)

# 7. A widget moved during playback: the Pull target changes at t = 0.5 s. The frames before
#    keep their values, the change applies from the frame shown on, the run after it is the run
#    restarted there with the new target, and it replays the same once its frames are evicted.
hand = SoftBodyCondition(Input=jelly, ConditionName="hand", ConditionType="Pull", Region="Sphere",
                         SphereCenter=[0.15, 0, 0.5], SphereRadius=0.04, PullTarget=[0.3, 0, 0.6],
                         PullStiffness=50)
live = SoftBody(Input=jelly, Conditions=[hand], EndTime=1.0, FrameInterval=0.1, TimeStep=1e-3)
before = {t: sbt.points_of(sbt.output_at(live, t)) for t in (0.3, 0.5)}
hand.PullTarget = [0.0, 0.3, 0.7]  # the handle moved while frame 0.5 s is shown
moved = sbt.output_at(live, 0.5)
sbt.check(np.array_equal(sbt.points_of(moved), before[0.5]), "live change: the frame shown keeps its value")
sbt.check(np.array_equal(sbt.points_of(sbt.output_at(live, 0.3)), before[0.3]), "live change: earlier frames keep theirs")
after = sbt.output_at(live, 1.0)
changes = after.GetFieldData().GetArray("ConditionChangeTimes")
sbt.check(changes is not None and changes.GetNumberOfTuples() == 1 and abs(changes.GetValue(0) - 0.5) < 1e-12,
          "live change: field data ConditionChangeTimes records it at 0.5 s")
restart_input = PVTrivialProducer()
at_rest = moved.NewInstance()
at_rest.DeepCopy(moved)
at_rest.GetPoints().SetData(numpy_support.numpy_to_vtk(sbt.points_of(moved) - sbt.point_array(moved, "Displacement"), deep=True))
restart_input.GetClientSideObject().SetOutput(at_rest)
hand_then = SoftBodyCondition(Input=restart_input, ConditionName="hand", ConditionType="Pull", Region="Sphere",
                              SphereCenter=[0.15, 0, 0.5], SphereRadius=0.04, PullTarget=[0.0, 0.3, 0.7],
                              PullStiffness=50)
# The sphere selects by rest position: the same points as on the jelly.
resumed = SoftBody(Input=restart_input, Conditions=[hand_then], InitialDisplacementArray="Displacement",
                   InitialVelocityArray="Velocity", EndTime=0.5, FrameInterval=0.1, TimeStep=1e-3)
gap = float(np.abs(sbt.points_of(sbt.output_at(resumed, 0.5)) - sbt.points_of(after)).max())
sbt.check(gap < 1e-9, f"live change: the run after it is the run restarted there with the new target (gap {gap:.1e} m)")
live.CacheMemoryLimit = 0  # evicts every frame but 0
replayed = sbt.points_of(sbt.output_at(live, 1.0))
sbt.check(np.array_equal(replayed, sbt.points_of(after)), "live change: replayed from frame 0 it gives the same run")
Delete(resumed)
Delete(live)

# 5. Bad conditions.
errors = sbt.ErrorCapture()
other = SoftBodyCondition(Input=box, ConditionName="elsewhere", Region="All points")
for label, properties, words in [
        ("set from another mesh", {"Input": jelly, "Conditions": [other]},
         ["Condition 'elsewhere'", "is not a point of the body"]),
        ("pressure on no face", {"Input": box, "Conditions": [SoftBodyCondition(
            Input=box, ConditionName="lid", ConditionType="Pressure", Region="Sphere",
            SphereCenter=[0, 0, 0], SphereRadius=0.01, Pressure=10.0)]},
         ["Condition 'lid' (Pressure)", "none of the body's boundary faces"])]:
    errors.clear()
    body = SoftBody(EndTime=0.1, FrameInterval=0.1, **properties)
    out = sbt.output_at(body, 0.1)
    text = "".join(errors.errors)
    sbt.check(builtins.all(w in text for w in words), f"{label}: refused naming {words} ({text.strip()[:160]!r})")
    sbt.check(out is None or out.GetNumberOfPoints() == 0, f"{label}: the output is empty")
    Delete(body)
errors.clear()
nothing = SoftBodyCondition(Input=box, ConditionName="nothing", Region="Sphere", SphereCenter=[9, 9, 9],
                            SphereRadius=0.1)
nothing.UpdatePipeline()
text = "".join(errors.warnings)
sbt.check("Condition 'nothing': its sphere selects none of the input's" in text,
          f"empty region: warned by name ({text.strip()[:160]!r})")
errors.close()
print("python.conditions: all checks passed")
