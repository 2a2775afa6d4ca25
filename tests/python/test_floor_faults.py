"""python.floor_faults: what can go wrong with bodies on the floor (crushed tets, a skin below
the floor, a lifted body that rises, no rebound), measured through the filter as a new user
meets it (test_floor_start.py covers the torus started half below the floor; the unit tests
cover the core kernels). Every number checked is printed.

(a) XPBD ellipsoid (Tetrahedralize Surface of a scaled Sphere) resting on the floor: inverted
    tets (VolumeRatio <= 0) after 0.04 s and 0.2 s: none at the defaults (10 iterations x 1
    substep) and with 4 substeps, with the default material or XPBD Material = Young's Modulus
    (compliances from E per tet). Three measures keep tets from
    crushing: a tet below a tenth of its rest volume is projected as a hard inequality
    (pbd_kernels.h); while a tet with a corner held by the floor is still inverted after the
    global iterations, the contact region alone is iterated on, bottom up; and after the
    contacts, which come last in each iteration and would flatten the bottom layer again, a held
    tet is raised back to the least volume without moving into the floor (pbd_held_tets.cpp).
    No point is below the floor in any run. Every frame counts its inverted tets (field data
    InvertedTets) and one that has any warns with the remedy (Substeps): checked here, with a
    run of 2 iterations that leaves some.
(b) Mass-Spring on the same ellipsoid: no inverted tet (the ellipsoid rather than `spot`, which
    takes 10 s per 0.2 s here and stands on hooves small enough to crush at E = 1e5 Pa).
(c) Voxelized `spot` and `bunny_10k.obj` (shared data; skipped when absent) under XPBD: the
    skinned Surface is never below the floor by more than the contact margin, and the floor's
    render correction is what keeps it there (it moves vertices that the skin alone draws
    deeper); the body lifted onto the floor does not rise.
(d) Restitution changes a tet bar's rebound under PBD and XPBD: dropped
    from h = 0.3 m, its lowest point comes back up about e^2 h."""

import builtins
import os

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())
SHARED = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "data")


def inverted(mesh):
    return int((sbt.cell_array(mesh, "VolumeRatio") <= 0.0).sum())


def check_inversion_report(body, found, label, remedy):
    """Every frame counts its inverted tets in field data InvertedTets, and a frame with any
    carries the warning with the method's remedy; one without carries no such warning."""
    for t, count in zip((0.04, 0.2), found):
        mesh = sbt.output_at(body, t)
        reported = sbt.field_value(mesh, "InvertedTets")
        warnings = sbt.field_value(mesh, "Warnings") or ""
        sbt.check(reported == count, f"{label}, t = {t} s: InvertedTets {reported} is the count of VolumeRatio <= 0 ({count})")
        warned = f"{count} of " in warnings and "tets are inverted" in warnings and remedy in warnings
        sbt.check(warned == (count > 0), f"{label}, t = {t} s: the inversion warning with its remedy is there "
                  f"exactly when a tet is inverted ({count}; warnings: {warnings!r})")


def on_floor(source):
    """`source` moved up or down so that its lowest point is on the floor z = 0."""
    source.UpdatePipeline()
    bounds = source.GetDataInformation().GetBounds()
    moved = Transform(Input=source)
    moved.Transform.Translate = [0.0, 0.0, -bounds[4]]
    return moved


def ellipsoid_tets(resolution):
    """A TetGen ellipsoid 1 x 0.6 x 0.4 m resting on the floor."""
    ellipsoid = Transform(Input=Sphere(Radius=0.5, ThetaResolution=resolution, PhiResolution=resolution))
    ellipsoid.Transform.Scale = [1.0, 0.6, 0.4]
    return TetrahedralizeSurfaceTetGen(Input=on_floor(ellipsoid))


# (a) and (b)
tets = ellipsoid_tets(48)
count = sbt.output_at(tets, 0.0).GetNumberOfCells()
for label, props in [("XPBD defaults", dict(Method="XPBD")),
                     ("XPBD, 4 substeps", dict(Method="XPBD", Substeps=4)),
                     ("XPBD, Young's modulus, 4 substeps", dict(Method="XPBD", XPBDMaterial="Young's Modulus", Substeps=4)),
                     ("XPBD, 2 iterations", dict(Method="XPBD", Iterations=2))]:
    body = SoftBody(Input=tets, EndTime=0.2, FrameInterval=0.04, **props)
    found = [inverted(sbt.output_at(body, t)) for t in (0.04, 0.2)]
    lowest = builtins.min(float(sbt.points_of(sbt.output_at(body, t))[:, 2].min()) for t in (0.04, 0.2))
    check_inversion_report(body, found, label, "Raise Substeps")
    print(f"(a) {label}: ellipsoid of {count} tets resting on the floor: {found[0]} inverted after "
          f"0.04 s, {found[1]} after 0.2 s; lowest point z = {lowest:.2e} m")
    if "2 iterations" in label:
        # Far from converged: some tets stay inverted, which is what the report is for.
        sbt.check(found[1] > 0, f"(a) {label}: the under-iterated solve leaves inverted tets to report")
    else:
        sbt.check(found == [0, 0], f"(a) {label}: no tet inverts at floor contact")
    sbt.check(lowest >= 0.0, f"(a) {label}: no point below the floor")
    Delete(body)

coarse = ellipsoid_tets(24)   # mass-spring's explicit step is short: a coarser mesh
body = SoftBody(Input=coarse, Method="Mass-Spring", EndTime=0.2, FrameInterval=0.04)
found = [inverted(sbt.output_at(body, t)) for t in (0.04, 0.2)]
check_inversion_report(body, found, "Mass-Spring", "raise YoungsModulus")
print(f"(b) Mass-Spring: ellipsoid of {sbt.output_at(coarse, 0.0).GetNumberOfCells()} tets on the "
      f"floor: {found[0]} inverted after 0.04 s, {found[1]} after 0.2 s")
sbt.check(found == [0, 0], "(b) Mass-Spring: no tet inverts at floor contact")
Delete(body)

# (c) Voxelized public meshes under XPBD, their own surface skinned on.
for name, path in [("spot", os.path.join(SHARED, "keenan-spot", "spot_triangulated.obj")),
                   ("bunny", os.path.join(SHARED, "PositionBasedDynamics", "bunny_10k.obj"))]:
    if not os.path.isfile(path):
        print(f"(c) shared data absent: {path} not read, {name} skipped")
        continue
    surface = Clean(Input=OpenDataFile(path))   # the OBJ reader repeats every triangle's corners
    lattice = SoftBodyVoxelize(Input=surface)    # 20 voxels along the longest side
    lattice.UpdatePipeline()
    spacing = sbt.field_value(lattice.GetClientSideObject().GetOutputDataObject(0), "LatticeSpacing")
    margin = 0.1 * 0.5 * spacing   # automatic: a tenth of the particle radius
    # The meshes lie partly below z = 0: lifted onto that floor (FloorPlacement Automatic would
    # put the floor under them instead), so the lift is what (c) also checks.
    body = SoftBody(Input=lattice, Surface=surface, Method="XPBD", EndTime=2.0, FrameInterval=0.04,
                    FloorPlacement="Through Floor Origin")
    body.UpdatePipelineInformation()
    lowest, moved, deepest = np.inf, 0, 0.0
    com0 = sbt.center_of_mass(sbt.output_at(body, 0.0, sbt.PARTICLES_PORT))[2]
    highest, rising = com0, 0.0
    for t in list(body.TimestepValues)[::5]:
        skinned = sbt.output_at(body, t, 3)
        lowest = builtins.min(lowest, float(sbt.points_of(skinned)[:, 2].min()))
        moved = builtins.max(moved, int(sbt.field_value(skinned, "SkinnedMovedOntoFloor")))
        deepest = builtins.max(deepest, sbt.field_value(skinned, "SkinnedDeepestBelowFloor"))
        particles = sbt.output_at(body, t, sbt.PARTICLES_PORT)
        m = 1.0 / sbt.point_array(particles, "InverseMass")
        v = sbt.point_array(particles, "Velocity")
        highest = builtins.max(highest, sbt.center_of_mass(particles)[2])
        rising = builtins.max(rising, float((m * v[:, 2]).sum() / m.sum()))
    print(f"(c) {name}, voxelized at {spacing:.4f} m, XPBD, 2 s: lowest skinned vertex z = {lowest:.2e} m "
          f"(margin {margin:.2e} m); the floor correction moved up to {moved} vertices, from up to "
          f"{deepest:.4f} m below; centre of mass {com0:.4f} m at the start, highest {highest:.4f} m, "
          f"largest upward speed {rising:.3f} m/s")
    sbt.check(lowest >= -margin, f"(c) {name}: the skinned Surface is not below the floor beyond the margin")
    sbt.check(moved > 0 and deepest > margin,
              f"(c) {name}: the correction is what keeps it there (the skin alone draws it {deepest:.4f} m below)")
    sbt.check(highest < com0 + 1e-3 and rising < 0.5, f"(c) {name}: the body does not rise")
    Delete(body)

# (d) Restitution: a 0.3 x 0.06 x 0.06 m tet bar dropped flat from 0.3 m.
h = 0.3
bar = TetrahedralizeSurfaceTetGen(Input=Triangulate(Input=Box(
    XLength=0.3, YLength=0.06, ZLength=0.06, Center=[0.0, 0.0, h + 0.03])),
    MaxTetVolume=2e-6, MaxTetVolumeIsRelative=0)
for method in ["PBD", "XPBD"]:
    rebound = {}
    for e in [0.0, 0.5, 1.0]:
        body = SoftBody(Input=bar, Method=method, Restitution=e, EndTime=0.8, FrameInterval=0.01)
        body.UpdatePipelineInformation()
        low = np.array([sbt.points_of(sbt.output_at(body, t, sbt.PARTICLES_PORT))[:, 2].min()
                        for t in body.TimestepValues])
        landed = int(np.argmax(low < 0.02))
        sbt.check(low[landed] < 0.02, f"(d) {method}, e = {e}: the bar reaches the floor")
        # The height it comes back up to, above where it rests (the contact margin).
        rebound[e] = float(low[landed:].max() - low[-1])
        Delete(body)
    print(f"(d) {method}: rebound of the lowest point after a {h} m drop, e = 0 / 0.5 / 1: "
          f"{rebound[0.0]:.4f} / {rebound[0.5]:.4f} / {rebound[1.0]:.4f} m "
          f"(e^2 h = 0 / {0.25 * h:.3f} / {h:.3f} m)")
    sbt.check(rebound[0.0] < 0.05 * h, f"(d) {method}: e = 0 does not bounce")
    sbt.check(0.5 * 0.25 * h < rebound[0.5] < 1.5 * 0.25 * h, f"(d) {method}: e = 0.5 rebounds about e^2 h")
    sbt.check(rebound[1.0] > 0.75 * h, f"(d) {method}: e = 1 rebounds nearly to h")
print("python.floor_faults passed")
