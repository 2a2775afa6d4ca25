"""Generate the project's own small meshes (run with pvpython).

    pvpython data/make_meshes.py [--output-dir data] [--check]

Writes:
  jelly.vtu  a rounded box ("jelly"), 0.30 x 0.30 x 0.20 m, centred at (0, 0, 0.40) so its bottom
             is 0.30 m above the floor z = 0. 567 points, 2304 tetrahedra, no point or cell arrays.

  torus.vtp  a closed triangle surface for the voxelized-body demo: a torus (ring radius 0.20 m,
             tube radius 0.08 m) tilted 30 degrees about x, centred at (0, 0, 0.50). 48 x 24
             quads split into triangles, indices wrapping around so the surface is closed and
             manifold without merging points. Checked: closed, consistently oriented outward,
             and its volume within 2% of 2 pi^2 R r^2 (the 24-gon
             tube section holds 98.9% of the circle's area).

How the jelly is built (deterministic, no random numbers, no Delaunay):
  1. A structured 8 x 8 x 6 grid of hexahedra over the cube [-1, 1]^3, each hexahedron split into
     the 6 tetrahedra of the Kuhn (Freudenthal) subdivision. All hexahedra use the same main
     diagonal, so the faces between neighbours match (the mesh is conforming). A Kuhn tetrahedron
     has dihedral angles of 45, 60 and 90 degrees only: no slivers.
  2. The cube is rounded by blending each point with its image under the cube-to-sphere map
     x' = x sqrt(1 - y^2/2 - z^2/2 + y^2 z^2/3) (and cyclic), p = (1 - a) cube + a sphere with
     a = ROUNDING. The map is smooth, so the tetrahedra stay well shaped; step 4 checks it.
  3. Scaled to the half extents and moved to the centre above.
  4. Checks: every tetrahedron is oriented with a positive volume (the VTK convention: the
     fourth point lies on the side the right-handed normal of (p0, p1, p2) points to), the
     minimum dihedral angle, the total volume, and that the surface is closed and manifold.
     The script fails (exit status 1) if any check fails.

--check only reads the existing files and runs the checks.
"""

import argparse
import itertools
import os
import sys

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import VTK_TETRA, vtkCellArray, vtkUnstructuredGrid
from vtkmodules.vtkFiltersCore import vtkFeatureEdges
from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter
from vtkmodules.vtkFiltersVerdict import vtkMeshQuality
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter

# --- jelly.vtu parameters -------------------------------------------------------------------
JELLY_CELLS = (8, 8, 6)            # hexahedra along x, y, z (each split into 6 tetrahedra)
JELLY_HALF_EXTENTS = (0.15, 0.15, 0.10)   # m
JELLY_CENTER = (0.0, 0.0, 0.40)    # m: bottom at z = 0.30 m above the floor z = 0
ROUNDING = 0.35                    # 0 = box, 1 = ellipsoid

# Quality thresholds the checks demand.
MIN_DIHEDRAL_DEG = 25.0


def kuhn_tets():
    """The 6 Kuhn tetrahedra of the unit hexahedron as corner indices (bit 0 = x, 1 = y, 2 = z).

    Each is the path 0 -> e_a -> e_a + e_b -> 7 for a permutation (a, b, c) of the axes.
    """
    tets = []
    for perm in itertools.permutations(range(3)):
        corner = 0
        path = [corner]
        for axis in perm:
            corner |= 1 << axis
            path.append(corner)
        tets.append(path)
    return tets


def rounded_box_points(cells, half_extents, center, rounding):
    nx, ny, nz = cells
    u = [np.linspace(-1.0, 1.0, n + 1) for n in cells]
    # Point (i, j, k) has index i + (nx + 1) * (j + (ny + 1) * k).
    z, y, x = np.meshgrid(u[2], u[1], u[0], indexing="ij")
    x, y, z = x.ravel(), y.ravel(), z.ravel()
    x2, y2, z2 = x * x, y * y, z * z
    sx = x * np.sqrt(1.0 - y2 / 2.0 - z2 / 2.0 + y2 * z2 / 3.0)
    sy = y * np.sqrt(1.0 - z2 / 2.0 - x2 / 2.0 + z2 * x2 / 3.0)
    sz = z * np.sqrt(1.0 - x2 / 2.0 - y2 / 2.0 + x2 * y2 / 3.0)
    cube = np.stack([x, y, z], axis=1)
    sphere = np.stack([sx, sy, sz], axis=1)
    p = (1.0 - rounding) * cube + rounding * sphere
    return p * np.asarray(half_extents) + np.asarray(center)


def structured_tets(cells):
    nx, ny, nz = cells

    def pid(i, j, k):
        return i + (nx + 1) * (j + (ny + 1) * k)

    local = kuhn_tets()
    tets = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                corners = [pid(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))
                           for c in range(8)]
                for t in local:
                    tets.append([corners[c] for c in t])
    return np.asarray(tets, dtype=np.int64)


def signed_volumes(points, tets):
    p0, p1, p2, p3 = (points[tets[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", np.cross(p1 - p0, p2 - p0), p3 - p0) / 6.0


def orient_positive(points, tets):
    """Swap two corners of every tetrahedron with a negative signed volume."""
    tets = tets.copy()
    neg = signed_volumes(points, tets) < 0.0
    tets[neg, 1], tets[neg, 2] = tets[neg, 2].copy(), tets[neg, 1].copy()
    return tets


def dihedral_angles_deg(points, tets):
    """All 6 interior dihedral angles of every tetrahedron, shape (n, 6), in degrees."""
    p = [points[tets[:, i]] for i in range(4)]
    faces = [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]   # face i is opposite corner i
    normals = []
    for i, (a, b, c) in enumerate(faces):
        n = np.cross(p[b] - p[a], p[c] - p[a])
        # Orient outwards: away from the opposite corner.
        s = np.sign(np.einsum("ij,ij->i", n, p[a] - p[i]))[:, None]
        n = n * s
        normals.append(n / np.linalg.norm(n, axis=1)[:, None])
    angles = []
    for i, j in itertools.combinations(range(4), 2):
        cos = -np.einsum("ij,ij->i", normals[i], normals[j])
        angles.append(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
    return np.stack(angles, axis=1)


def to_grid(points, tets):
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetData(numpy_support.numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64),
                                           deep=True))
    grid.SetPoints(pts)
    cells = vtkCellArray()
    offsets = numpy_support.numpy_to_vtkIdTypeArray(
        np.arange(0, 4 * len(tets) + 1, 4, dtype=np.int64), deep=True)
    conn = numpy_support.numpy_to_vtkIdTypeArray(
        np.ascontiguousarray(tets.ravel(), dtype=np.int64), deep=True)
    cells.SetData(offsets, conn)
    grid.SetCells(VTK_TETRA, cells)
    return grid


def from_grid(grid):
    points = numpy_support.vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    n = grid.GetNumberOfCells()
    types = [grid.GetCellType(i) for i in range(n)]
    if any(t != VTK_TETRA for t in types):
        raise ValueError("mesh holds cells other than tetrahedra")
    conn = numpy_support.vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    return points, conn.reshape(-1, 4).astype(np.int64)


def check(name, grid):
    """Print the mesh statistics; return a list of failures."""
    failures = []
    points, tets = from_grid(grid)
    vol = signed_volumes(points, tets)
    dih = dihedral_angles_deg(points, tets)

    quality = vtkMeshQuality()
    quality.SetInputData(grid)
    quality.SetTetQualityMeasureToMinAngle()   # minimum dihedral angle, as Verdict defines it
    quality.Update()
    q = numpy_support.vtk_to_numpy(quality.GetOutput().GetCellData().GetArray("Quality"))

    surface = vtkGeometryFilter()
    surface.SetInputData(grid)
    edges = vtkFeatureEdges()
    edges.SetInputConnection(surface.GetOutputPort())
    edges.BoundaryEdgesOn()
    edges.NonManifoldEdgesOn()
    edges.FeatureEdgesOff()
    edges.ManifoldEdgesOff()
    edges.Update()
    open_edges = edges.GetOutput().GetNumberOfCells()

    lo, hi = points.min(axis=0), points.max(axis=0)
    print(f"{name}: {len(points)} points, {len(tets)} tetrahedra")
    print(f"  bounds x [{lo[0]:.4f}, {hi[0]:.4f}]  y [{lo[1]:.4f}, {hi[1]:.4f}]"
          f"  z [{lo[2]:.4f}, {hi[2]:.4f}] m")
    print(f"  total volume {vol.sum():.6e} m^3, tet volume min {vol.min():.4e} max {vol.max():.4e}"
          f" m^3 (max/min {vol.max() / vol.min():.2f})")
    print(f"  dihedral angle min {dih.min():.2f} max {dih.max():.2f} deg"
          f" (vtkMeshQuality MinAngle min {q.min():.2f} deg)")
    print(f"  open or non-manifold surface edges: {open_edges}")
    if not (vol > 0.0).all():
        failures.append(f"{name}: {(vol <= 0.0).sum()} tetrahedra with volume <= 0")
    if dih.min() < MIN_DIHEDRAL_DEG:
        failures.append(f"{name}: minimum dihedral angle {dih.min():.2f} < {MIN_DIHEDRAL_DEG} deg")
    if open_edges != 0:
        failures.append(f"{name}: surface has {open_edges} open or non-manifold edges")
    used = np.zeros(len(points), dtype=bool)
    used[tets.ravel()] = True
    if not used.all():
        failures.append(f"{name}: {(~used).sum()} points belong to no tetrahedron")
    return failures


# --- torus.vtp parameters -------------------------------------------------------------------
TORUS_RING, TORUS_TUBE = 0.20, 0.08      # m
TORUS_SEGMENTS = (48, 24)                # around the ring, around the tube
TORUS_TILT_DEG = 30.0
TORUS_CENTER = (0.0, 0.0, 0.50)


def make_torus():
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    n, m = TORUS_SEGMENTS
    u = 2.0 * np.pi * np.arange(n) / n
    v = 2.0 * np.pi * np.arange(m) / m
    uu, vv = np.meshgrid(u, v, indexing="ij")          # point (i, j) has index i * m + j
    x = (TORUS_RING + TORUS_TUBE * np.cos(vv)) * np.cos(uu)
    y = (TORUS_RING + TORUS_TUBE * np.cos(vv)) * np.sin(uu)
    z = TORUS_TUBE * np.sin(vv)
    p = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    t = np.radians(TORUS_TILT_DEG)
    tilt = np.array([[1, 0, 0], [0, np.cos(t), -np.sin(t)], [0, np.sin(t), np.cos(t)]])
    p = p @ tilt.T + np.asarray(TORUS_CENTER)
    triangles = []
    for i in range(n):
        for j in range(m):
            a, b = i * m + j, ((i + 1) % n) * m + j
            c, d = ((i + 1) % n) * m + (j + 1) % m, i * m + (j + 1) % m
            triangles += [(a, b, c), (a, c, d)]   # counter-clockwise seen from outside
    points = vtkPoints()
    points.SetData(numpy_support.numpy_to_vtk(p, deep=True))
    polys = vtkCellArray()
    for tri in triangles:
        polys.InsertNextCell(3, tri)
    surface = vtkPolyData()
    surface.SetPoints(points)
    surface.SetPolys(polys)
    return surface


def check_surface(name, surface):
    """Closed, manifold, outward-oriented, with the torus's volume; returns failures."""
    from vtkmodules.vtkFiltersCore import vtkMassProperties
    failures = []
    edges = vtkFeatureEdges()
    edges.SetInputData(surface)
    edges.BoundaryEdgesOn()
    edges.NonManifoldEdgesOn()
    edges.FeatureEdgesOff()
    edges.ManifoldEdgesOff()
    edges.Update()
    open_edges = edges.GetOutput().GetNumberOfCells()
    # Signed volume from the divergence theorem: positive when the triangles face outward.
    p = numpy_support.vtk_to_numpy(surface.GetPoints().GetData())
    tri = numpy_support.vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    signed = np.einsum("ij,ij->i", p[tri[:, 0]], np.cross(p[tri[:, 1]], p[tri[:, 2]])).sum() / 6.0
    mass = vtkMassProperties()
    mass.SetInputData(surface)
    mass.Update()
    exact = 2.0 * np.pi ** 2 * TORUS_RING * TORUS_TUBE ** 2
    print(f"{name}: {len(p)} points, {len(tri)} triangles, open or non-manifold edges {open_edges}, "
          f"signed volume {signed:.6e} m^3 (torus {exact:.6e})")
    if open_edges:
        failures.append(f"{name}: {open_edges} open or non-manifold edges")
    if not signed > 0:
        failures.append(f"{name}: triangles face inward")
    if abs(signed / exact - 1.0) > 0.02:
        failures.append(f"{name}: volume {signed:.4e} not within 2% of {exact:.4e}")
    return failures


def make_jelly():
    points = rounded_box_points(JELLY_CELLS, JELLY_HALF_EXTENTS, JELLY_CENTER, ROUNDING)
    tets = orient_positive(points, structured_tets(JELLY_CELLS))
    return to_grid(points, tets)


def write(grid, path):
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(grid)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()      # raw binary
    writer.SetCompressorTypeToZLib()
    if writer.Write() != 1:
        raise RuntimeError(f"could not write {path}")


def read(path):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfPoints() == 0:
        raise RuntimeError(f"could not read {path}")
    return grid


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output-dir", default=here, help="where to write (default: data/)")
    parser.add_argument("--check", action="store_true",
                        help="only check the existing files, write nothing")
    args = parser.parse_args()

    failures = []
    path = os.path.join(args.output_dir, "jelly.vtu")
    if args.check:
        grid = read(path)
    else:
        os.makedirs(args.output_dir, exist_ok=True)
        grid = make_jelly()
        failures += check("jelly (generated)", grid)
        if not failures:
            write(grid, path)
            grid = read(path)
    if not failures:
        failures += check(path, grid)
        print(f"  file size {os.path.getsize(path)} bytes")

    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPolyDataWriter
    torus_path = os.path.join(args.output_dir, "torus.vtp")
    if not args.check:
        surface = make_torus()
        failures += check_surface("torus (generated)", surface)
        writer = vtkXMLPolyDataWriter()
        writer.SetFileName(torus_path)
        writer.SetInputData(surface)
        writer.SetCompressorTypeToZLib()
        if writer.Write() != 1:
            failures.append(f"could not write {torus_path}")
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(torus_path)
    reader.Update()
    if reader.GetOutput().GetNumberOfPoints() == 0:
        failures.append(f"could not read {torus_path}")
    else:
        failures += check_surface(torus_path, reader.GetOutput())

    for f in failures:
        print("FAILED:", f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
