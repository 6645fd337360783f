"""ParaView state test: loads each state of paraview_states/ against an output/
directory the way a user does (data directory search, restricted to it),
checks the sources, arrays and ranges, renders each state offscreen to PNG
and checks that the picture is not blank and shows what it should.

    pvbatch check_states.py --states paraview_states --data WORK/output --images WORK/images

Exit code 0 when every check passes; otherwise 1, listing every failed check.
"""
import argparse
import math
import os
import sys
import tempfile

from paraview.simple import *  # noqa: F401,F403 (ParaView's scripting API)
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter
from vtkmodules.vtkCommonDataModel import vtkImageData
import numpy as np

FAILURES = []


def check(ok, what):
    print(("  ok    " if ok else "  FAIL  ") + what)
    if not ok:
        FAILURES.append(what)
    return ok


# --- data checks ------------------------------------------------------------
def source(name):
    s = FindSource(name)
    check(s is not None, "source '%s' exists" % name)
    return s


def file_name(proxy):
    fn = proxy.GetProperty("FileName")
    if fn is None:
        return None
    v = proxy.FileName
    return v if isinstance(v, str) else (v[0] if len(v) else None)


def reader(data, rel):
    """The reader of file `rel`, found under the given output/ directory
    (ParaView names readers after their files, so find it by file name)."""
    want = os.path.realpath(os.path.join(data, rel))
    found = [(k[0], file_name(p)) for k, p in GetSources().items() if file_name(p)]
    for (name, fn), p in zip(found, [p for p in GetSources().values() if file_name(p)]):
        if os.path.basename(fn) == os.path.basename(rel):
            check(os.path.realpath(fn) == want,
                  "reader '%s' relocated to %s (got %r)" % (name, want, fn))
            return p
    check(False, "a reader of %s exists (readers: %s)" % (rel, found))
    return None


def array_info(src, assoc, name):
    info = src.GetDataInformation().DataInformation
    attrs = info.GetAttributeInformation({"POINTS": 0, "CELLS": 1}[assoc])
    return attrs.GetArrayInformation(name) if attrs else None


def has_array(src, assoc, name, ncomp):
    a = array_info(src, assoc, name)
    if not check(a is not None, "%s has %s array '%s'" % (src.GetXMLLabel() if hasattr(src, "GetXMLLabel") else "source", assoc.lower(), name)):
        return None
    check(a.GetNumberOfComponents() == ncomp,
          "'%s' has %d components (got %d)" % (name, ncomp, a.GetNumberOfComponents()))
    return a.GetComponentRange(-1 if ncomp > 1 else 0) if ncomp > 1 else a.GetComponentRange(0)


def n_points(src):
    return src.GetDataInformation().GetNumberOfPoints()


def n_cells(src):
    return src.GetDataInformation().GetNumberOfCells()


def check_plane(data):
    plane = reader(data, "field/plane.vti")
    if plane is None:
        return None
    plane.UpdatePipeline()
    b = plane.GetDataInformation().GetBounds()
    check(b[4] == b[5], "plane.vti is 2-D (z extent %g..%g)" % (b[4], b[5]))
    check(b[0] < -2.4 and b[1] > 2.4 and b[2] < -2.4 and b[3] > 2.4,
          "plane covers the probe circle r0 = 2.4 mm (bounds %s)" % (b[:4],))
    r = has_array(plane, "POINTS", "Bz", 1)
    has_array(plane, "POINTS", "B", 3)
    if r:
        lo, hi = r
        amp = max(abs(lo), abs(hi))
        check(1e-3 < amp < 2.0, "plane |Bz| max %.4g T is plausible (1 mT .. 2 T)" % amp)
        check(abs(hi + lo) < 0.15 * amp,
              "plane Bz range [%.4g, %.4g] T is nearly antisymmetric (diametric magnet)" % (lo, hi))
    return plane


def check_bz_lut(vmax_hint=None):
    lut = GetColorTransferFunction("Bz_mT")
    pts = lut.RGBPoints
    lo, hi = pts[0], pts[-4]
    check(hi > 0 and abs(lo + hi) <= 1e-9 * hi, "Bz colour map symmetric about 0 ([%g, %g] mT)" % (lo, hi))
    mid = [pts[i:i + 4] for i in range(0, len(pts), 4)]
    c_lo, c_hi = mid[0][1:], mid[-1][1:]
    check(c_lo[2] > c_lo[0] and c_hi[0] > c_hi[2], "Bz colour map diverges blue (-) to red (+)")
    view = GetActiveView()
    bar = GetScalarBar(lut, view)
    check(bar.Visibility == 1 and "mT" in bar.Title, "Bz scalar bar visible, in mT (title %r)" % bar.Title)
    return lo, hi


def check_plane_bz(data):
    plane = check_plane(data)
    bz = source("plane_Bz_mT")
    if bz is not None and plane is not None:
        bz.UpdatePipeline()
        r_mT = has_array(bz, "POINTS", "Bz_mT", 1)
        r_T = array_info(plane, "POINTS", "Bz")
        if r_mT and r_T:
            check(abs(r_mT[1] - 1000 * r_T.GetComponentRange(0)[1]) < 1e-6 * abs(r_mT[1]) + 1e-9,
                  "Bz_mT = 1000 * Bz")
    iso = source("isolines")
    if iso is not None:
        iso.UpdatePipeline()
        check(n_points(iso) > 50, "isolines are non-empty (%d points)" % n_points(iso))
    circ = source("probe_circle")
    if circ is not None:
        check(abs(circ.MajorRadiusVector[0] - 2.4) < 1e-9, "probe circle radius r0 = 2.4 mm")
    for k, (x, y) in enumerate(((2.4, 0.0), (0.0, 2.4))):
        p = source("probe_%d" % k)
        if p is not None:
            c = p.Center
            check(abs(c[0] - x) < 1e-9 and abs(c[1] - y) < 1e-9,
                  "probe %d at (%g, %g) mm (array two, %d deg)" % (k, x, y, 90 * k))
    check_bz_lut()


def check_magnet_field(data):
    mesh = reader(data, "field/mesh.vtu")
    if mesh is not None:
        mesh.UpdatePipeline()
        check(n_cells(mesh) > 100, "mesh has cells (%d)" % n_cells(mesh))
        has_array(mesh, "POINTS", "psi", 1)
        rb = has_array(mesh, "CELLS", "B", 3)
        if rb:
            check(0.3 < rb[1] < 3.0, "|B| max %.3g T is plausible for Br = 1.2 T" % rb[1])
        rr = has_array(mesh, "CELLS", "region", 1)
        if rr:
            check(rr[0] <= 1 <= rr[1] and rr[1] >= 2, "region ids include magnet (1) and air (2): %s" % (rr,))
    clip = source("clip_y0")
    if clip is not None:
        clip.UpdatePipeline()
        # Crinkle clip: whole cells that reach y >= 0, so a strict subset of the
        # mesh that still spans y > 0 and cuts through the magnet (region 1).
        b = clip.GetDataInformation().GetBounds()
        mb = mesh.GetDataInformation().GetBounds() if mesh is not None else b
        total = n_cells(mesh) if mesh is not None else float("inf")
        check(0 < n_cells(clip) < total, "clip keeps part of the mesh (%d of %s cells)" % (n_cells(clip), total))
        check(b[3] > 0 and b[2] > mb[2] + 1e-9, "clip keeps the y >= 0 side (y from %g to %g; mesh from %g)" % (b[2], b[3], mb[2]))
    st = source("streamlines")
    if st is not None:
        st.UpdatePipeline()
        npt = n_points(st)
        check(npt > 200, "stream lines are non-empty (%d points)" % npt)
        if npt:
            b = st.GetDataInformation().GetBounds()
            check(b[1] - b[0] > 4.0 and b[5] - b[4] > 4.0,
                  "stream lines leave the magnet (x %g..%g, z %g..%g mm)" % (b[0], b[1], b[4], b[5]))
    check_plane(data)
    check_bz_lut()


def check_probe_paths(data, paths_rel):
    check_plane(data)
    paths = reader(data, paths_rel)
    if paths is None:
        return
    paths.UpdatePipeline()
    check(n_cells(paths) >= 2, "paths: one polyline per probe (%d polylines)" % n_cells(paths))
    check(n_points(paths) >= 2 * 16, "paths have points (%d)" % n_points(paths))
    rb = has_array(paths, "POINTS", "Bz", 1)
    rt = has_array(paths, "POINTS", "theta_deg", 1)
    has_array(paths, "POINTS", "probe", 1)
    if rt:
        check(rt[0] == 0.0 and 300.0 < rt[1] < 360.0, "theta_deg covers one turn [%g, %g]" % rt)
    if rb:
        check(rb[0] < 0 < rb[1] and max(abs(rb[0]), abs(rb[1])) < 2.0,
              "path Bz changes sign over a turn and is plausible [%g, %g] T" % rb)
    b = paths.GetDataInformation().GetBounds()
    r = max(abs(v) for v in b[:4])
    check(1.5 < r < 5.0, "paths lie around the probe circle (max |x|,|y| = %.3g mm)" % r)
    start = source("paths_start")
    if start is not None:
        start.UpdatePipeline()
        check(n_points(start) > 0, "theta = 0 markers exist")
    check_bz_lut()


STEEL_CUP = os.path.join("steel_parts", "steel_cup")


def check_steel_parts_B(data):
    """steel_parts_B: abs(B) on the axis plane y = 0 of the steel_parts study's steel cup, the
    outlines of the magnet (region 1) and the cup (region 10), B's direction."""
    sl = reader(data, os.path.join(STEEL_CUP, "slice_y0.vti"))
    if sl is not None:
        sl.UpdatePipeline()
        b = sl.GetDataInformation().GetBounds()
        check(b[2] == b[3] == 0.0, "slice_y0.vti is the plane y = 0 (y extent %g..%g)" % (b[2], b[3]))
        check(b[0] < -2.5 and b[1] > 2.5 and b[4] < -2.5 and b[5] > 4.55,
              "slice covers the cup and the sensing plane (bounds %s)" % (b,))
        rb = has_array(sl, "POINTS", "B", 3)
        if rb:
            # Point values, not cell centroids: next to the cup's inner corner the P2 gradient at a node
            # exceeds the centroid's (mu_r is per cell) and reaches ~4.7 T on the study's mesh.
            check(0.3 < rb[1] < 8.0, "slice abs(B) max %.3g T is plausible (0.3 .. 8 T)" % rb[1])
    absb = source("slice_absB_T")
    if absb is not None:
        absb.UpdatePipeline()
        r = has_array(absb, "POINTS", "absB_T", 1)
        if r and sl is not None and array_info(sl, "POINTS", "B"):
            check(abs(r[1] - array_info(sl, "POINTS", "B").GetComponentRange(-1)[1]) < 1e-6 * r[1],
                  "absB_T = abs(B) of the slice")
    bodies = reader(data, os.path.join(STEEL_CUP, "bodies.vtu"))
    if bodies is not None:
        bodies.UpdatePipeline()
        check(n_cells(bodies) > 100, "bodies.vtu has cells (%d)" % n_cells(bodies))
        has_array(bodies, "CELLS", "B", 3)
        rr = has_array(bodies, "CELLS", "region", 1)
        if rr:
            check(rr[0] == 1, "bodies.vtu has the magnet region (1): region ids %g..%g" % rr)
            check(rr[1] == 10, "bodies.vtu has the part region (10): region ids %g..%g" % rr)
    for name, half_width in (("magnet_section", 2.0), ("part_section", 2.5)):
        sec = source(name)
        if sec is None:
            continue
        sec.UpdatePipeline()
        b = sec.GetDataInformation().GetBounds()
        ok = n_points(sec) > 10
        check(ok, "%s (the outline on y = 0) is non-empty (%d points)" % (name, n_points(sec)))
        if ok:
            check(abs(-b[0] - half_width) < 0.3 and abs(b[1] - half_width) < 0.3,
                  "%s spans x = +-%g mm (%g..%g)" % (name, half_width, b[0], b[1]))
    arrows = source("B_arrows")
    if arrows is not None:
        arrows.UpdatePipeline()
        check(n_points(arrows) > 100, "B direction arrows are non-empty (%d points)" % n_points(arrows))
    lut = GetColorTransferFunction("absB_T")
    lo, hi = lut.RGBPoints[0], lut.RGBPoints[-4]
    check(lut.UseLogScale == 1 and lo > 0 and hi / lo >= 100,
          "abs(B) colour map is logarithmic over >= 2 decades ([%g, %g] T)" % (lo, hi))
    check(2.0 <= hi <= 3.0, "abs(B) colour map reaches steel's saturation (top %g T)" % hi)
    bar = GetScalarBar(lut, GetActiveView())
    check(bar.Visibility == 1 and "[T]" in bar.Title, "abs(B) scalar bar visible, in T (title %r)" % bar.Title)


# --- image checks -----------------------------------------------------------
def read_png(path):
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    nx, ny, _ = img.GetDimensions()
    a = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(ny, nx, -1)[::-1, :, :3]  # row 0 = top
    return a.astype(np.int32)


def image_stats(a):
    flat = a.reshape(-1, 3)
    bg = np.array([255, 255, 255])
    non_bg = np.mean(np.any(np.abs(flat - bg) > 8, axis=1))
    distinct = len(np.unique(flat[:, 0] * 65536 + flat[:, 1] * 256 + flat[:, 2]))
    return non_bg, distinct


def reddish(a):
    return (a[..., 0] > a[..., 2] + 40)


def bluish(a):
    return (a[..., 2] > a[..., 0] + 40)


def self_test_image_metric(tmpdir):
    """The blank-image check must be able to fail: a uniform image is blank."""
    img = vtkImageData()
    img.SetDimensions(64, 48, 1)
    img.AllocateScalars(3, 3)
    vtk_to_numpy(img.GetPointData().GetScalars())[:] = 255
    path = os.path.join(tmpdir, "blank_selftest.png")
    w = vtkPNGWriter()
    w.SetFileName(path)
    w.SetInputData(img)
    w.Write()
    non_bg, distinct = image_stats(read_png(path))
    check(non_bg == 0.0 and distinct == 1, "image metric calls a uniform white image blank")


def check_image(name, path):
    a = read_png(path)
    non_bg, distinct = image_stats(a)
    h, w, _ = a.shape
    check(distinct >= 200, "%s.png has %d distinct colours (>= 200)" % (name, distinct))
    check(non_bg >= {"plane_bz": 0.35, "magnet_field": 0.35, "probe_paths": 0.5, "steel_parts_B": 0.35}[name],
          "%s.png: %.0f%% of pixels are not background" % (name, 100 * non_bg))
    if name in ("plane_bz", "probe_paths"):
        # Top view, x to the right: Bz > 0 (red) for x > 0, < 0 (blue) for x < 0.
        mid = a[h // 4: 3 * h // 4, :, :]
        left, right = mid[:, w // 8: 3 * w // 8], mid[:, 5 * w // 8 - w // 16: 7 * w // 8 - w // 16]
        check(reddish(right).mean() > 0.2 and bluish(left).mean() > 0.2,
              "%s.png: red (Bz > 0) on the +x side, blue on the -x side (%.2f, %.2f)"
              % (name, reddish(right).mean(), bluish(left).mean()))
    if name == "steel_parts_B":
        # Turbo map, log scale: the magnet and the cup (~1..2 T) dark red, the air around (5..50 mT) blue-cyan.
        high = (a[..., 0] > 120) & (a[..., 1] < 90) & (a[..., 2] < 60)
        air = (a[..., 2] > 150) & (a[..., 0] < 120)
        check(high.mean() > 0.02 and air.mean() > 0.05,
              "steel_parts_B.png shows high abs(B) (dark red, %.1f%%) and the air's low abs(B) (blue, %.1f%%)"
              % (100 * high.mean(), 100 * air.mean()))
    if name == "magnet_field":
        magnet_red = (a[..., 0] > 110) & (a[..., 0] > 2.5 * a[..., 1]) & (a[..., 0] > 2.5 * a[..., 2])
        check(magnet_red.mean() > 0.005, "magnet_field.png shows the magnet region (%.2f%% red)"
              % (100 * magnet_red.mean()))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--states", required=True)
    ap.add_argument("--data", required=True,
                    help="an output/ directory (field/, probe_paths/, steel_parts/steel_cup/)")
    ap.add_argument("--images", required=True, help="where to write the rendered PNGs")
    ap.add_argument("--paths", default=os.path.join("probe_paths", "paths_example.vtp"),
                    help="probe paths file relative to --data")
    ap.add_argument("--size", default="900x760")
    a = ap.parse_args()
    data = os.path.abspath(a.data)
    os.makedirs(a.images, exist_ok=True)
    size = [int(v) for v in a.size.split("x")]
    sizes = {"steel_parts_B": [1000, 860]}   # the state's own view size (text and colour bar fit)
    with tempfile.TemporaryDirectory() as tmp:
        self_test_image_metric(tmp)

    for name in ("plane_bz", "magnet_field", "probe_paths", "steel_parts_B"):
        print("state", name)
        ResetSession()
        state = os.path.join(a.states, name + ".pvsm")
        if not check(os.path.isfile(state), "%s exists" % state):
            continue
        try:
            LoadState(state, data_directory=data, restrict_to_data_directory=True)
        except Exception as e:  # noqa: BLE001 (report and go on)
            check(False, "LoadState(%s): %s" % (name, e))
            continue
        view = GetActiveView() or GetRenderViews()[0]
        SetActiveView(view)
        {"plane_bz": lambda: check_plane_bz(data), "magnet_field": lambda: check_magnet_field(data),
         "probe_paths": lambda: check_probe_paths(data, a.paths),
         "steel_parts_B": lambda: check_steel_parts_B(data)}[name]()
        png = os.path.join(a.images, name + ".png")
        SaveScreenshot(png, view, ImageResolution=sizes.get(name, size), OverrideColorPalette="WhiteBackground")
        if check(os.path.isfile(png), "rendered " + png):
            check_image(name, png)

    if FAILURES:
        print("\n%d check(s) failed:" % len(FAILURES))
        for f in FAILURES:
            print("  " + f)
        sys.exit(1)
    print("\nall ParaView state checks passed")


if __name__ == "__main__":
    main()
