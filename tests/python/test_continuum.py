"""python.continuum: the finite-element material models through the filter, as a pvpython user
runs them.

1. A bar hanging from its pinned top face (nu = 0, Static): the elongation is rho g L^2 / (2E)
   within 0.5 % for both models, each layer of cells carries the weight below it (mean
   CauchyStress zz = rho g z within 1 % of the top's stress, von Mises within 5 %), GreenStrain and CauchyStress are six-component cell arrays with
   point-averaged copies, ElasticEnergy is in field data and KineticEnergy is 0.
2. The bundled jelly (a TetGen mesh) under Stable Neo-Hookean and Implicit Euler drops onto the
   floor and rests there with no inverted tet.
3. A per-cell YoungsModulusArray (a two-material bar) hangs by the sum of its halves, under the
   static solve and under XPBD (a softer copy of the array, Corotated); under XPBD with
   compliances the array is refused as one it would not read.
4. The jelly under XPBD with each continuum model (its tets held by deviatoric and hydrostatic
   constraints) lands and rests with no inverted tet, the plan names the model, and the stress
   and energy come out as under Mass-Spring; Corotated with nu < 0 is refused there.
5. What cannot run is refused with the pairing that works: PBD with a continuum model, Static
   without pinned points, nu out of (-1, 0.5), a missing cell array (also under PBD)."""

import builtins
import os
import tempfile

import numpy as np
from paraview.simple import *  # noqa: F401,F403

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())
workdir = tempfile.mkdtemp(prefix="softbody_continuum_")

G, RHO, E = 9.81, 1100.0, 1.0e7
CELL, ALONG = 0.01, 20
LENGTH = CELL * ALONG
path, rest = sbt.write_tet_box(workdir, 2, 2, ALONG, CELL,
                               pinned=lambda p: p[2] > LENGTH - 1e-9)
bar = XMLUnstructuredGridReader(FileName=[path])
expected = RHO * G * LENGTH ** 2 / (2 * E)
for model in ("Corotated", "Stable Neo-Hookean"):
    body = SoftBody(Input=bar, MaterialModel=model, Integrator="Static", PinnedPointsArray="Pinned",
                    YoungsModulus=E, PoissonRatio=0.0, Density=RHO, Floor=0, EndTime=0.1,
                    FrameInterval=0.1, ImplicitTolerance=1e-8, MassDistribution="Lumped Volume")
    mesh = sbt.output_at(body, 0.1)
    x = sbt.points_of(mesh)
    bottom = rest[:, 2] < 1e-9
    elongation = float(np.mean(rest[bottom, 2] - x[bottom, 2]))
    print(f"{model}: elongation {elongation:.6e} m, rho g L^2 / (2E) = {expected:.6e} m")
    sbt.check(abs(elongation / expected - 1) < 5e-3, f"{model}: hanging bar within 0.5 %")
    # Equilibrium: each layer of cells carries the weight below it, so its mean vertical stress
    # is rho g z at the layer's middle (single tets of a Kuhn cell share it unevenly). That needs
    # the finite-element lumping of the mass (a quarter of each tet to each corner): the
    # thesis's default gives the bottom row of points a full layer's mass.
    cells = mesh.GetNumberOfCells()
    heights = np.array([np.mean([rest[mesh.GetCell(c).GetPointId(k), 2] for k in range(4)])
                        for c in range(cells)])
    layer = np.floor(heights / CELL).astype(int)
    sigma_zz = sbt.cell_array(mesh, "CauchyStress")[:, 2]
    von_mises = sbt.cell_array(mesh, "VonMisesStress")
    top = RHO * G * LENGTH
    print("  layer sigma_zz / (rho g z_mid):", np.round([sigma_zz[layer == k].mean() / (RHO * G * (k + 0.5) * CELL) for k in range(ALONG)], 4))
    worst_zz = max(abs(sigma_zz[layer == k].mean() - RHO * G * (k + 0.5) * CELL) for k in range(ALONG)) / top
    worst_vm = max(abs(von_mises[layer == k].mean() - RHO * G * (k + 0.5) * CELL) for k in range(ALONG)) / top
    sbt.check(worst_zz < 0.01, f"{model}: each layer's mean CauchyStress zz is rho g z (worst {worst_zz:.2e} of the top's)")
    sbt.check(worst_vm < 0.05, f"{model}: each layer's mean von Mises stress is rho g z (worst {worst_vm:.2e})")
    for name in ("GreenStrain", "CauchyStress"):
        array = mesh.GetCellData().GetArray(name)
        sbt.check(array is not None and array.GetNumberOfComponents() == 6
                  and array.GetNumberOfTuples() == cells, f"{model}: cell array {name}, 6 components")
    sbt.check(mesh.GetPointData().GetArray("VonMisesStress") is not None
              and mesh.GetPointData().GetArray("CauchyStress") is not None,
              f"{model}: point-averaged stresses for smooth colouring")
    elastic = sbt.field_value(mesh, "ElasticEnergy")
    sbt.check(elastic is not None and elastic > 0, f"{model}: ElasticEnergy {elastic} J in field data")
    sbt.check(sbt.field_value(mesh, "KineticEnergy") == 0.0, f"{model}: Static has no kinetic energy")
    Delete(body)

# Per-cell Young's modulus from a cell array (top half four times stiffer): the elongation is
# rho g L^2 / 8 (1 / E_bottom + 3 / E_top) in uniaxial stress.
two = ProgrammableFilter(Input=bar)
two.Script = (f"import numpy as np\n"
              f"from vtkmodules.util import numpy_support\n"
              f"grid = self.GetInput()\n"
              f"out = self.GetOutput()\n"
              f"out.ShallowCopy(grid)\n"
              f"z = np.array([np.mean([grid.GetPoint(grid.GetCell(c).GetPointId(k))[2] for k in range(4)]) "
              f"for c in range(grid.GetNumberOfCells())])\n"
              f"e = numpy_support.numpy_to_vtk(np.where(z > {LENGTH / 2}, {4 * E}, {E}), deep=True)\n"
              f"e.SetName('E')\n"
              f"out.GetCellData().AddArray(e)\n"
              f"soft = numpy_support.numpy_to_vtk(np.where(z > {LENGTH / 2}, {4 * E / 100}, {E / 100}), deep=True)\n"
              f"soft.SetName('ESoft')\n"
              f"out.GetCellData().AddArray(soft)\n")
body = SoftBody(Input=two, MaterialModel="Corotated", Integrator="Static", PinnedPointsArray="Pinned",
                YoungsModulusArray="E", PoissonRatio=0.0, Density=RHO, Floor=0, EndTime=0.1,
                FrameInterval=0.1, ImplicitTolerance=1e-8, MassDistribution="Lumped Volume")
mesh = sbt.output_at(body, 0.1)
x = sbt.points_of(mesh)
bottom = rest[:, 2] < 1e-9
elongation = float(np.mean(rest[bottom, 2] - x[bottom, 2]))
expected_two = RHO * G * LENGTH ** 2 / 8 * (1 / E + 3 / (4 * E))
print(f"two materials: elongation {elongation:.6e} m, expected {expected_two:.6e} m")
sbt.check(abs(elongation / expected_two - 1) < 5e-3, "per-cell YoungsModulusArray: two-material bar within 0.5 %")
Delete(body)

# The same under XPBD, a hundred times softer (XPBD's iterations carry a soft bar's weight; the
# rest state is within a percent of the law's equilibrium at 16 substeps).
body = SoftBody(Input=two, Method="XPBD", MaterialModel="Corotated", PinnedPointsArray="Pinned",
                YoungsModulusArray="ESoft", PoissonRatio=0.0, Density=RHO, Floor=0, Substeps=16,
                VelocityDamping=5.0, EndTime=2.5, FrameInterval=2.5, MassDistribution="Lumped Volume")
mesh = sbt.output_at(body, 2.5)
x = sbt.points_of(mesh)
elongation = float(np.mean(rest[bottom, 2] - x[bottom, 2]))
print(f"two materials under XPBD: elongation {elongation:.6e} m, expected {100 * expected_two:.6e} m")
sbt.check(abs(elongation / (100 * expected_two) - 1) < 0.02,
          "per-cell YoungsModulusArray under XPBD: two-material bar within 2 %")
Delete(body)
errors = sbt.ErrorCapture()
body = SoftBody(Input=two, Method="XPBD", YoungsModulusArray="ESoft", EndTime=0.1, FrameInterval=0.1)
out = sbt.output_at(body, 0.1)
text = "".join(errors.errors)
sbt.check("would be ignored" in text and (out is None or out.GetNumberOfPoints() == 0),
          f"XPBD with compliances refuses a YoungsModulusArray it would not read ({text.strip()[:160]!r})")
Delete(body)

jelly = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
body = SoftBody(Input=jelly, MaterialModel="Stable Neo-Hookean", Integrator="Implicit Euler",
                EndTime=1.5, FrameInterval=1.0 / 30)
mesh = sbt.output_at(body, 1.5)
x = sbt.points_of(mesh)
v = sbt.point_array(mesh, "Velocity")
print(sbt.field_summary(mesh))
sbt.check(np.isfinite(x).all(), "jelly: finite state")
sbt.check(sbt.field_value(mesh, "InvertedTets") == 0, "jelly: no tet inverted by the landing")
sbt.check(x[:, 2].min() > -1e-9 and x[:, 2].min() < 0.01, "jelly: rests on the floor")
sbt.check(float(np.abs(v).max()) < 0.05, f"jelly: settled (max speed {np.abs(v).max():.3g} m/s)")
sbt.check("tets, Stable Neo-Hookean" in (sbt.field_value(mesh, "Plan") or ""), "jelly: the plan names the model")
Delete(body)

for model in ("Corotated", "Stable Neo-Hookean"):
    body = SoftBody(Input=jelly, Method="XPBD", MaterialModel=model, Substeps=4,
                    VelocityDamping=2.0, EndTime=1.5, FrameInterval=1.0 / 30)
    mesh = sbt.output_at(body, 1.5)
    x = sbt.points_of(mesh)
    v = sbt.point_array(mesh, "Velocity")
    plan = sbt.field_value(mesh, "Plan") or ""
    print(f"XPBD {model}: lowest {x[:, 2].min():.4f} m, max speed {np.abs(v).max():.3g} m/s, plan {plan!r}")
    sbt.check(np.isfinite(x).all(), f"XPBD {model}: finite state")
    sbt.check(sbt.field_value(mesh, "InvertedTets") == 0, f"XPBD {model}: no tet inverted by the landing")
    sbt.check(x[:, 2].min() > -1e-3 and x[:, 2].min() < 0.01, f"XPBD {model}: rests on the floor")
    sbt.check(float(np.abs(v).max()) < 0.05, f"XPBD {model}: settled")
    sbt.check(f"tet elasticity: XPBD Gauss-Seidel, {model}" in plan, f"XPBD {model}: the plan names the model")
    sbt.check(mesh.GetCellData().GetArray("VonMisesStress") is not None, f"XPBD {model}: VonMisesStress out")
    elastic = sbt.field_value(mesh, "ElasticEnergy")
    sbt.check(elastic is not None and elastic > 0, f"XPBD {model}: ElasticEnergy {elastic} J (the jelly rests squeezed)")
    Delete(body)

for label, properties, words in [
        ("PBD", {"Method": "PBD", "MaterialModel": "Corotated"}, ["Method Mass-Spring and XPBD"]),
        ("XPBD Corotated nu < 0", {"Method": "XPBD", "MaterialModel": "Corotated", "PoissonRatio": -0.2},
         ["PoissonRatio -0.2", "Stable Neo-Hookean in [-0.5, 0.5)"]),
        ("Static unheld", {"Integrator": "Static", "MaterialModel": "Corotated"}, ["0 fixed points"]),
        ("nu = 0.5", {"MaterialModel": "Corotated", "PoissonRatio": 0.5}, ["PoissonRatio", "got 0.5"]),
        ("nu = -1", {"MaterialModel": "Stable Neo-Hookean", "PoissonRatio": -1.0}, ["PoissonRatio", "got -1"]),
        ("missing cell array", {"MaterialModel": "Corotated", "YoungsModulusArray": "NoSuchArray"},
         ["YoungsModulusArray", "NoSuchArray"]),
        ("missing cell array with PBD", {"Method": "PBD", "DensityArray": "NoSuchArray"},
         ["DensityArray", "NoSuchArray"])]:
    errors.clear()
    body = SoftBody(Input=jelly, EndTime=0.1, FrameInterval=0.1, **properties)
    out = sbt.output_at(body, 0.1)
    text = "".join(errors.errors)
    # builtins': the star imports above bring VTK's array `all`, which takes no generator.
    sbt.check(builtins.all(w in text for w in words), f"{label}: refused naming {words} ({text.strip()[:160]!r})")
    sbt.check(out is None or out.GetNumberOfPoints() == 0, f"{label}: the output is empty")
    Delete(body)
print("python.continuum: all checks passed")
