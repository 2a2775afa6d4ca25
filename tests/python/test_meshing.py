"""python.meshing: the meshing proxies as a user reaches them from pvpython: OpenDataFile on a
.msh and a .node file picks the plugin's readers, and TetrahedralizeSurface on Sphere() feeds a
SoftBody.

pvpython names a proxy's function after its label, so the proxy TetrahedralizeSurface (label
"Tetrahedralize Surface (TetGen)") is called as TetrahedralizeSurfaceTetGen()."""

import os
import shutil
import tempfile

from paraview.simple import *  # noqa: F401,F403 (the pvpython API, as users write it)

import softbody_testing as sbt

args = sbt.parse_args(__doc__)
LoadPlugin(args.plugin, remote=False, ns=globals())
sbt.check("TetrahedralizeSurfaceTetGen" in globals(),
          "LoadPlugin defines TetrahedralizeSurfaceTetGen()")

# Small files written here: one tet in Gmsh 4.1 and in TetGen format.
folder = tempfile.mkdtemp(prefix="softbody_python_meshing_")
try:
    msh = os.path.join(folder, "tet.msh")
    with open(msh, "w") as f:
        f.write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
                "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n")
    with open(os.path.join(folder, "tet.node"), "w") as f:
        f.write("4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n")
    with open(os.path.join(folder, "tet.ele"), "w") as f:
        f.write("1 4 0\n0 0 1 2 3\n")

    for path, proxy_name in ((msh, "GmshReader"), (os.path.join(folder, "tet.node"), "TetGenReader"),
                             (os.path.join(folder, "tet.ele"), "TetGenReader")):
        reader = OpenDataFile(path)
        sbt.check(reader is not None and reader.GetXMLName() == proxy_name,
                  f"OpenDataFile({os.path.basename(path)}) uses {proxy_name} "
                  f"({reader.GetXMLName() if reader else None})")
        out = sbt.output_at(reader, 0.0)
        sbt.check(out.GetNumberOfPoints() == 4 and out.GetNumberOfCells() == 1,
                  f"{os.path.basename(path)}: 4 points, 1 tet")
        Delete(reader)

    # A broken file is an error message, not a crash of pvpython.
    bad = os.path.join(folder, "bad.msh")
    with open(bad, "w") as f:
        f.write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n")
    errors = sbt.ErrorCapture()
    reader = OpenDataFile(bad)
    out = sbt.output_at(reader, 0.0)
    sbt.check(out.GetNumberOfCells() == 0, "truncated .msh: empty output")
    sbt.check(any("bad.msh:" in e for e in errors.errors),
              f"truncated .msh: the error names the file and line ({errors.errors[:1]})")
    errors.close()
    Delete(reader)
finally:
    shutil.rmtree(folder, ignore_errors=True)

# The public mesh when present.
sphere5k = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared",
                        "data", "IPC", "sphere5K.msh")
if os.path.isfile(sphere5k):
    out = sbt.output_at(OpenDataFile(sphere5k), 0.0)
    sbt.check(out.GetNumberOfPoints() == 7034 and out.GetNumberOfCells() == 27792,
              f"sphere5K.msh: 7034 points, 27792 tets ({out.GetNumberOfPoints()}, "
              f"{out.GetNumberOfCells()})")
else:
    print("shared data absent: sphere5K.msh not read")

# An OBJ surface as users bring it (ParaView's OBJ reader repeats every triangle's corners).
sphere_obj = os.path.join(os.path.dirname(sphere5k), "..", "PositionBasedDynamics", "sphere.obj")
if os.path.isfile(sphere_obj):
    obj_tets = TetrahedralizeSurfaceTetGen(Input=OpenDataFile(sphere_obj))
    out = sbt.output_at(obj_tets, 0.0)
    sbt.check(out.GetNumberOfCells() > 1000, f"sphere.obj: tetrahedralized ({out.GetNumberOfCells()} tets)")

# Surface -> tets -> simulated body, in one pipeline.
sphere = Sphere(Radius=0.1, Center=[0.0, 0.0, 0.3], ThetaResolution=24, PhiResolution=16)
tets = TetrahedralizeSurfaceTetGen(Input=sphere)
sbt.check(tets.GetXMLName() == "TetrahedralizeSurface", f"proxy name ({tets.GetXMLName()})")
sbt.check(tets.GetXMLLabel() == "Tetrahedralize Surface (TetGen)", f"label ({tets.GetXMLLabel()})")
sbt.check(tets.MaxRadiusEdgeRatio == 2.0 and tets.MaxTetVolume == 0.0 and
          tets.PreserveBoundary == 0 and tets.MaxTetVolumeIsRelative == 0 and
          tets.MaxAddedPoints == 200000, "defaults")
tets.MaxTetVolume = 1e-3
tets.MaxTetVolumeIsRelative = 1
mesh = sbt.output_at(tets, 0.0)
n_tets = mesh.GetNumberOfCells()
sbt.check(n_tets > 500, f"relative MaxTetVolume 1e-3 gives > 500 tets ({n_tets})")
body = SoftBody(Input=tets, EndTime=0.2)
moved = sbt.output_at(body, 0.2)
sbt.check(moved.GetNumberOfCells() == n_tets, "SoftBody simulates the tets")
sbt.check(moved.GetBounds()[5] < 0.4 - 1e-3, f"the body fell (top z {moved.GetBounds()[5]})")
print("python.meshing passed")
