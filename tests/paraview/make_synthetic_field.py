"""Synthetic stand-in for solve_field's output (development and fallback only).

Writes DIR/mesh.vtu, DIR/plane.vti, DIR/box.vti with the file names and arrays
of docs/interfaces.md, from the exact field of the default magnet (docs/physics.md: the
magnetization as a surface charge M0*cos(phi') on the curved face, z'
integrated analytically, midpoint rule in phi'). The "mesh" is a tetrahedralized
box, not a FEM mesh; `psi` is the dipole potential. Used by the ParaView state
test only when solve_field is not built (tests/CMakeLists.txt says which).

With --steel-cup DIR it also writes the stand-in of the steel_parts study's
field files: DIR/slice_y0.vti (the magnet's exact field in air, no cup, on
the plane y = 0) and DIR/bodies.vtu (tets of a box inside the magnet, region
1, and inside the study's default cup, region 10).

Usage: pvbatch make_synthetic_field.py --out DIR [--steel-cup DIR] [--omit ARRAY]
(--omit drops one array everywhere, or with `part` the cup's cells: to check
that the state test fails.)
"""
import argparse
import math
import os

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkThreshold
from vtkmodules.vtkFiltersGeneral import vtkDataSetTriangleFilter
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLUnstructuredGridWriter

R, L, BR, H = 2.0, 4.0, 1.2, 2.55   # mm, mm, T, mm (docs/physics.md defaults)
ZS = L / 2 + H


def exact_B(p, n_phi=256):
    """B [T] at points p (N x 3, mm), outside the magnet (inside: + Br x)."""
    x, y, z = p[:, 0:1], p[:, 1:2], p[:, 2:3]
    phi = (np.arange(n_phi) + 0.5) * 2 * math.pi / n_phi
    c, s = np.cos(phi)[None, :], np.sin(phi)[None, :]
    dx, dy = x - R * c, y - R * s
    rho2 = np.maximum(dx * dx + dy * dy, 1e-12)
    up, um = z + L / 2, z - L / 2
    g = lambda u: u / (rho2 * np.sqrt(rho2 + u * u))
    fz = 1 / np.sqrt(rho2 + um * um) - 1 / np.sqrt(rho2 + up * up)
    fr = g(up) - g(um)
    k = BR * R / (4 * math.pi) * (2 * math.pi / n_phi)
    B = np.stack([k * np.sum(c * dx * fr, axis=1), k * np.sum(c * dy * fr, axis=1),
                  k * np.sum(c * fz, axis=1)], axis=1)
    inside = (np.hypot(p[:, 0], p[:, 1]) < R) & (np.abs(p[:, 2]) < L / 2)
    B[inside, 0] += BR
    return B


def image(origin, spacing, dims):
    img = vtkImageData()
    img.SetOrigin(*origin)
    img.SetSpacing(*spacing)
    img.SetDimensions(*dims)
    return img


def points_of(img):
    n = img.GetNumberOfPoints()
    return np.array([img.GetPoint(i) for i in range(n)])


def add(data, name, arr, omit):
    if name == omit:
        return
    a = numpy_to_vtk(np.ascontiguousarray(arr), deep=1)
    a.SetName(name)
    data.AddArray(a)


def write(writer_cls, data, path):
    w = writer_cls()
    w.SetFileName(path + ".tmp")
    w.SetInputData(data)
    w.SetDataModeToAppended()
    if not w.Write():
        raise SystemExit("cannot write " + path)
    os.replace(path + ".tmp", path)


def tets_of_box(origin, spacing, dims):
    """A box of images cells split into tetrahedra; returns (grid, cell centroids N x 3)."""
    tf = vtkDataSetTriangleFilter()
    tf.SetInputData(image(origin, spacing, dims))
    tf.Update()
    ug = tf.GetOutput()
    pts = vtk_to_numpy(ug.GetPoints().GetData())
    conn = vtk_to_numpy(ug.GetCells().GetConnectivityArray()).reshape(-1, 4)
    return ug, pts[conn].mean(axis=1)


def write_steel_cup(out, omit):
    """Stand-in for steel_parts' steel_cup/ (cup: bore R, wall and base 0.5 mm, z -2.5..1.5 mm)."""
    os.makedirs(out, exist_ok=True)
    sl = image((-5, 0, -5), (0.1, 1, 0.1), (101, 1, 112))
    add(sl.GetPointData(), "B", exact_B(points_of(sl)), omit)
    write(vtkXMLImageDataWriter, sl, os.path.join(out, "slice_y0.vti"))
    ug, cent = tets_of_box((-2.5, -2.5, -2.5), (0.25, 0.25, 0.25), (21, 21, 19))
    r = np.hypot(cent[:, 0], cent[:, 1])
    region = np.zeros(len(cent), dtype=np.int32)
    region[(r < R + 0.5) & (cent[:, 2] < 1.5)] = 10
    region[(r < R) & (np.abs(cent[:, 2]) < L / 2)] = 1
    if omit == "part":
        region[region == 10] = 0
    add(ug.GetCellData(), "region", region, omit)
    add(ug.GetCellData(), "B", exact_B(cent), omit)
    sel = vtkThreshold()   # the cells of the bodies (region >= 1)
    sel.SetInputData(ug)
    sel.SetInputArrayToProcess(0, 0, 0, 1, "region")
    sel.SetThresholdFunction(vtkThreshold.THRESHOLD_UPPER)
    sel.SetUpperThreshold(0.5)
    sel.Update()
    write(vtkXMLUnstructuredGridWriter, sel.GetOutput(), os.path.join(out, "bodies.vtu"))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True)
    ap.add_argument("--omit", default="")
    ap.add_argument("--steel-cup", default="")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)

    # plane.vti: 2-D, x and y -5..5 mm, z = z_s.
    plane = image((-5, -5, ZS), (0.1, 0.1, 1), (101, 101, 1))
    B = exact_B(points_of(plane))
    add(plane.GetPointData(), "Bz", B[:, 2], a.omit)
    add(plane.GetPointData(), "B", B, a.omit)
    write(vtkXMLImageDataWriter, plane, os.path.join(a.out, "plane.vti"))

    # box.vti: x, y -4..4 mm, z_s - 0.5 .. z_s + 0.5.
    box = image((-4, -4, ZS - 0.5), (0.2, 0.2, 0.1), (41, 41, 11))
    add(box.GetPointData(), "B", exact_B(points_of(box)), a.omit)
    write(vtkXMLImageDataWriter, box, os.path.join(a.out, "box.vti"))

    # mesh.vtu: tetrahedralized box -10..10 mm; region 1 magnet, 3 zone, 2 air.
    grid = image((-10, -10, -10), (1.0, 1.0, 1.0), (21, 21, 21))
    tf = vtkDataSetTriangleFilter()
    tf.SetInputData(grid)
    tf.Update()
    ug = tf.GetOutput()
    pts = np.array([ug.GetPoint(i) for i in range(ug.GetNumberOfPoints())])
    cent = np.zeros((ug.GetNumberOfCells(), 3))
    for i in range(ug.GetNumberOfCells()):
        ids = ug.GetCell(i).GetPointIds()
        cent[i] = pts[[ids.GetId(j) for j in range(ids.GetNumberOfIds())]].mean(axis=0)
    region = np.full(len(cent), 2, dtype=np.int32)
    zone = (np.abs(cent[:, 0]) < 5.5) & (np.abs(cent[:, 1]) < 5.5) & (np.abs(cent[:, 2] - ZS) < 1.0)
    region[zone] = 3
    region[(np.hypot(cent[:, 0], cent[:, 1]) < R) & (np.abs(cent[:, 2]) < L / 2)] = 1
    r3 = np.maximum(np.linalg.norm(pts, axis=1), R) ** 3
    psi = BR * math.pi * R * R * L / (4 * math.pi) * pts[:, 0] / r3
    add(ug.GetPointData(), "psi", psi, a.omit)
    add(ug.GetCellData(), "B", exact_B(cent), a.omit)
    add(ug.GetCellData(), "region", region, a.omit)
    write(vtkXMLUnstructuredGridWriter, ug, os.path.join(a.out, "mesh.vtu"))
    print("synthetic field written to", a.out)
    if a.steel_cup:
        write_steel_cup(a.steel_cup, a.omit)
        print("synthetic steel_parts field files written to", a.steel_cup)


if __name__ == "__main__":
    main()
