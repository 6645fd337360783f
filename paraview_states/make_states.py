"""Generates the ParaView 5.11 state files of paraview_states/ (reproducibly).

    paraview_states/pvbatch.sh paraview_states/make_states.py --data output [--states paraview_states]

--data is an output/ directory holding solve_field's field/ (plane.vti,
mesh.vtu) and probe_paths/paths_example.vtp (any case written by
magenc::write_probe_paths_vtp). The data are read to place things (sensing
plane height) and to choose colour ranges and isoline levels; then every file
name stored in the states is rewritten to the relative form
"output/<sub>/<file>", so a state opens against any output/ directory with
"Search files under specified directory" (GUI) or
LoadState(..., data_directory=<output>, restrict_to_data_directory=True).

States:
  plane_bz.pvsm       Bz on the sensing plane (mT, diverging map symmetric
                      about 0), isolines, probe circle r0, the probes of the
                      `two` array (0 and 90 deg), the magnet's outline.
  magnet_field.pvsm   mesh crinkle-clipped through the magnet (y = 0), coloured by
                      region; B stream lines (tubes, |B| log scale); the
                      sensing plane in place coloured by Bz.
  probe_paths.pvsm    probe paths of one mounting case (one polyline per
                      probe, drawn on top) over the plane's Bz and isolines.
  steel_parts_B.pvsm  the steel_parts study's steel cup: abs(B) [T, log scale]
                      on the plane y = 0 through the axis, the outlines of the
                      magnet and the cup, B's direction (arrows), the sensing
                      plane and the probes at +-r0. Reads
                      steel_parts/steel_cup/{slice_y0.vti, bodies.vtu}.
Source names (pipeline browser) are part of the contract that
tests/paraview/check_states.py checks: plane_Bz_mT, isolines, probe_circle,
probe_0, probe_1, magnet_outline, clip_y0, mesh_point_B, streamlines,
paths_on_top, paths_start, slice_absB_T, magnet_section, part_section,
B_arrows. Readers are named after their files (plane.vti, mesh.vtu,
paths_example.vtp, slice_y0.vti, bodies.vtu); ParaView renames a reader after
its new file when a state is loaded against other data, so the test finds
readers by file.

    --only NAME[,NAME]  writes only these states (e.g. steel_parts_B, whose
                        data come from the steel_parts study alone).
"""
import argparse
import math
import os
import re

from paraview import servermanager as sm
from paraview.simple import *  # noqa: F401,F403 (ParaView's scripting API)

R0_MM = 2.4                  # nominal probe radius (docs/physics.md default)
PROBE_ANGLES_DEG = (0, 90)   # default array `two`
MAGNET_R_MM, MAGNET_L_MM = 2.0, 4.0
PATHS_REL = os.path.join("probe_paths", "paths_example.vtp")
STEEL_CUP_REL = os.path.join("steel_parts", "steel_cup")   # the steel_parts study's field files
ABS_B_RANGE_T = (0.005, 2.5)   # log colour range of the steel_parts_B state: 5 mT .. above steel's saturation
WHITE, BLACK = [1, 1, 1], [0, 0, 0]
REGION_NAMES = {1: ("magnet", [0.85, 0.2, 0.15]), 2: ("air", [0.86, 0.86, 0.86]),
                3: ("refinement zone", [0.62, 0.78, 0.92]), 4: ("shaft", [0.45, 0.45, 0.5])}


def nice_step(x):
    """1, 2, 5 x 10^n not larger than x."""
    e = 10 ** math.floor(math.log10(x))
    for m in (5, 2, 1):
        if m * e <= x:
            return m * e
    return e


def new_view(size=(900, 760)):
    v = CreateView("RenderView")
    v.ViewSize = list(size)
    v.UseColorPaletteForBackground = 0
    v.Background = WHITE
    v.OrientationAxesVisibility = 1
    v.OrientationAxesLabelColor = BLACK
    return v


def solid(display, color):
    """Colour a representation with one colour (no array)."""
    display.ColorArrayName = ["POINTS", ""]
    display.AmbientColor = color
    display.DiffuseColor = color


def text(view, s, where="Upper Left Corner", size=14):
    t = Text(Text=s)
    d = Show(t, view)
    d.WindowLocation = where
    d.FontSize = size
    d.Color = BLACK
    return t


def bz_lut(vmax_mT):
    lut = GetColorTransferFunction("Bz_mT")
    lut.ApplyPreset("Cool to Warm", True)
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(-vmax_mT, vmax_mT)
    GetOpacityTransferFunction("Bz_mT").RescaleTransferFunction(-vmax_mT, vmax_mT)
    return lut


def style_bar(lut, view, title, where="Any Location", pos=(0.87, 0.1), length=0.5):
    bar = GetScalarBar(lut, view)
    bar.Title = title
    bar.ComponentTitle = ""
    bar.TitleColor = BLACK
    bar.LabelColor = BLACK
    bar.TitleFontSize = 16
    bar.LabelFontSize = 14
    bar.WindowLocation = where
    if where == "Any Location":
        bar.Position = list(pos)
    bar.ScalarBarLength = length
    bar.Visibility = 1
    return bar


def plane_bz(view, data, vmax_mT):
    """plane.vti read, Bz in mT (plane_Bz_mT) shown coloured on the symmetric map; returns
    (plane, bz, its display, lut, z_s)."""
    plane = XMLImageDataReader(registrationName="plane.vti",
                               FileName=[os.path.join(data, "field", "plane.vti")])
    plane.PointArrayStatus = ["Bz", "B"]
    plane.UpdatePipeline()
    z_s = plane.GetDataInformation().GetBounds()[4]
    bz = Calculator(registrationName="plane_Bz_mT", Input=plane)
    bz.ResultArrayName = "Bz_mT"
    bz.Function = "Bz*1000"
    d = Show(bz, view)
    ColorBy(d, ("POINTS", "Bz_mT"))
    lut = bz_lut(vmax_mT)
    d.LookupTable = lut
    return plane, bz, d, lut, z_s


def plane_with_isolines(view, data, vmax_mT, z_lift):
    """plane.vti coloured by Bz [mT] plus black isolines; returns (plane, bz, lut, z_s, step)."""
    plane, bz, _, lut, z_s = plane_bz(view, data, vmax_mT)

    step = nice_step(vmax_mT / 5.0)
    n = int(math.floor(vmax_mT / step))
    levels = [k * step for k in range(-n, n + 1)]
    iso = Contour(registrationName="isolines", Input=bz)
    iso.ContourBy = ["POINTS", "Bz_mT"]
    iso.Isosurfaces = levels
    iso.ComputeScalars = 1
    lifted = Transform(registrationName="isolines_lifted", Input=iso)
    lifted.Transform.Translate = [0, 0, z_lift]
    di = Show(lifted, view)
    solid(di, [0.15, 0.15, 0.15])
    di.LineWidth = 1.5
    return plane, bz, lut, z_s, step


def circle(name, radius, z, view, color, width=2.0):
    c = Ellipse(registrationName=name, Center=[0, 0, z], Normal=[0, 0, 1],
                MajorRadiusVector=[radius, 0, 0], Ratio=1.0, Resolution=240)
    d = Show(c, view)
    solid(d, color)
    d.LineWidth = width
    return c


def top_camera(view, z, half_width):
    view.CameraParallelProjection = 1
    view.CameraPosition = [0, 0, z + 50]
    view.CameraFocalPoint = [0, 0, z]
    view.CameraViewUp = [0, 1, 0]
    view.CameraParallelScale = half_width


def axes_grid(view, xtitle="x [mm]", ytitle="y [mm]", ztitle="z [mm]"):
    g = view.AxesGrid
    g.Visibility = 1
    g.XTitle, g.YTitle, g.ZTitle = xtitle, ytitle, ztitle
    for a in "XYZ":
        setattr(g, a + "TitleColor", BLACK)
        setattr(g, a + "LabelColor", BLACK)
    g.GridColor = [0.3, 0.3, 0.3]


def plane_range_mT(data):
    r = XMLImageDataReader(FileName=[os.path.join(data, "field", "plane.vti")])
    r.PointArrayStatus = ["Bz"]
    r.UpdatePipeline()
    lo, hi = r.PointData["Bz"].GetRange()
    Delete(r)
    return 1000 * max(abs(lo), abs(hi))


# ---------------------------------------------------------------------------
def make_plane_bz(data, vmax):
    view = new_view()
    plane, bz, lut, z_s, step = plane_with_isolines(view, data, vmax, 0.01)
    circle("magnet_outline", MAGNET_R_MM, z_s + 0.015, view, [0.35, 0.35, 0.35], 1.5)
    circle("probe_circle", R0_MM, z_s + 0.02, view, BLACK, 3.0)
    for k, b in enumerate(PROBE_ANGLES_DEG):
        a = math.radians(b)
        s = Sphere(registrationName="probe_%d" % k,
                   Center=[R0_MM * math.cos(a), R0_MM * math.sin(a), z_s + 0.05],
                   Radius=0.12, ThetaResolution=24, PhiResolution=24)
        d = Show(s, view)
        solid(d, [[0.0, 0.55, 0.1], [0.6, 0.0, 0.6]][k])
    style_bar(lut, view, "Bz [mT]")
    text(view, "Bz on the sensing plane z = %.2f mm (magnet frame, magnet at rest)\n"
               "black circle: probe circle r0 = %.1f mm;  grey: magnet outline R = %.0f mm\n"
               "probes of array 'two': green = 0 deg (cos), purple = 90 deg (sin)\n"
               "isolines every %g mT" % (z_s, R0_MM, MAGNET_R_MM, step), size=13)
    view.OrientationAxesVisibility = 0   # the axes grid labels x and y
    axes_grid(view)
    top_camera(view, z_s, 5.6)
    return view


def make_magnet_field(data, vmax):
    view = new_view((1000, 800))
    mesh = XMLUnstructuredGridReader(registrationName="mesh.vtu",
                                     FileName=[os.path.join(data, "field", "mesh.vtu")])
    mesh.CellArrayStatus = ["B", "region"]
    mesh.PointArrayStatus = ["psi"]
    mesh.UpdatePipeline()

    # 1. Half the mesh: keep the cells that reach y >= 0, so the cut faces the
    #    camera. Crinkle clip keeps whole cells: it shows the elements as they
    #    are and takes about a second on the default mesh (1.83M quadratic tets),
    #    where an exact clip of quadratic tets ran for minutes.
    clip = Clip(registrationName="clip_y0", Input=mesh)
    clip.ClipType = "Plane"
    clip.ClipType.Origin = [0, 0, 0]
    clip.ClipType.Normal = [0, -1, 0]
    clip.Invert = 1
    clip.Crinkleclip = 1
    dc = Show(clip, view)
    dc.SetRepresentationType("Surface With Edges")
    ColorBy(dc, ("CELLS", "region"))
    rlut = GetColorTransferFunction("region")
    rlut.InterpretValuesAsCategories = 1
    rlut.AnnotationsInitialized = 1
    ann, cols = [], []
    for rid, (name, col) in sorted(REGION_NAMES.items()):
        ann += [str(rid), name]
        cols += col
    rlut.Annotations = ann
    rlut.IndexedColors = cols
    dc.LookupTable = rlut
    dc.EdgeColor = [0.55, 0.55, 0.6]   # light: a fine mesh must not hide the region colours
    dc.Opacity = 0.5                  # translucent: the stream lines in the cut plane y = 0 show through
    rbar = style_bar(rlut, view, "region", pos=(0.03, 0.35), length=0.25)
    rbar.TextPosition = "Ticks left/bottom, annotations right/top"
    # The magnet's cells opaque over the translucent rest of the cut mesh.
    mag = Threshold(registrationName="magnet_cells", Input=clip)
    mag.Scalars = ["CELLS", "region"]
    mag.LowerThreshold = 1
    mag.UpperThreshold = 1
    dm = Show(mag, view)
    dm.SetRepresentationType("Surface With Edges")
    ColorBy(dm, ("CELLS", "region"))
    dm.LookupTable = rlut
    dm.EdgeColor = [0.55, 0.55, 0.6]

    # 2. Stream lines of B, seeded along the magnet axis inside the magnet;
    #    they stay in the symmetry plane y = 0 and close through the magnet.
    pdata = CellDatatoPointData(registrationName="mesh_point_B", Input=mesh)
    pdata.CellDataArraytoprocess = ["B"]
    st = StreamTracer(registrationName="streamlines", Input=pdata, SeedType="Line")
    st.Vectors = ["POINTS", "B"]
    st.SeedType.Point1 = [0, 0, -0.7 * MAGNET_L_MM / 2]
    st.SeedType.Point2 = [0, 0, 0.7 * MAGNET_L_MM / 2]
    st.SeedType.Resolution = 10
    st.IntegrationDirection = "BOTH"
    st.MaximumStreamlineLength = 60.0
    st.MaximumSteps = 4000
    tube = Tube(registrationName="streamline_tubes", Input=st)
    tube.Radius = 0.05
    tube.NumberofSides = 8
    dt = Show(tube, view)
    ColorBy(dt, ("POINTS", "B", "Magnitude"))
    blut = GetColorTransferFunction("B")
    blut.ApplyPreset("Viridis (matplotlib)", True)
    blut.AutomaticRescaleRangeMode = "Never"
    blut.RescaleTransferFunction(0.01, 1.5)
    blut.MapControlPointsToLogSpace()  # the preset's points spread evenly in log(|B|): without it most of
    blut.UseLogScale = 1               # the lines (below ~0.2 T) take the bottom colour
    dt.LookupTable = blut
    style_bar(blut, view, "|B| [T]", pos=(0.82, 0.5), length=0.38)

    # 3. The sensing plane in place, coloured by Bz.
    _, _, dp, lut, z_s = plane_bz(view, data, vmax)
    dp.Opacity = 0.85
    style_bar(lut, view, "Bz [mT]", pos=(0.82, 0.05), length=0.38)

    text(view, "Mesh cut at y = 0 (regions), stream lines of B (tubes),\n"
               "sensing plane z = %.2f mm coloured by Bz" % z_s, size=13)
    view.CameraParallelProjection = 1
    view.CameraFocalPoint = [0, 0, 1.2]
    el, az = math.radians(22), math.radians(-28)
    dist = 60.0
    view.CameraPosition = [dist * math.cos(el) * math.sin(az), -dist * math.cos(el) * math.cos(az),
                           1.2 + dist * math.sin(el)]
    view.CameraViewUp = [0, 0, 1]
    view.CameraParallelScale = 7.0
    return view


def make_probe_paths(data, vmax):
    view = new_view()
    plane, bz, lut, z_s, step = plane_with_isolines(view, data, vmax, 0.01)
    circle("magnet_outline", MAGNET_R_MM, z_s + 0.015, view, [0.35, 0.35, 0.35], 1.5)
    circle("probe_circle", R0_MM, z_s + 0.02, view, [0.1, 0.1, 0.1], 1.0)

    paths = XMLPolyDataReader(registrationName="paths_example.vtp", FileName=[os.path.join(data, PATHS_REL)])
    paths.PointArrayStatus = ["Bz", "theta_deg", "probe"]
    paths.CellArrayStatus = ["probe"]
    # Drawn on top: projected to 1 mm above the plane (the paths' true height
    # z_s + dz is in the file; a top view would hide paths below the plane).
    top = Calculator(registrationName="paths_on_top", Input=paths)
    top.CoordinateResults = 1
    top.Function = "coordsX*iHat + coordsY*jHat + %.6f*kHat" % (z_s + 1.0)
    tube = Tube(registrationName="paths_tubes", Input=top)
    tube.Radius = 0.035
    tube.NumberofSides = 8
    dt = Show(tube, view)
    ColorBy(dt, ("POINTS", "probe"))
    plut = GetColorTransferFunction("probe")
    plut.InterpretValuesAsCategories = 1
    plut.AnnotationsInitialized = 1
    plut.Annotations = ["0", "probe 0", "1", "probe 1", "2", "probe 2", "3", "probe 3"]
    plut.IndexedColors = [0.0, 0.55, 0.1, 0.6, 0.0, 0.6, 0.9, 0.6, 0.0, 0.0, 0.0, 0.0]
    dt.LookupTable = plut
    pbar = style_bar(plut, view, "path", pos=(0.03, 0.06), length=0.2)
    pbar.TextPosition = "Ticks left/bottom, annotations right/top"

    # Where each probe is at theta = 0: clip the polylines at theta <= 1e-6 deg
    # (keeps the first point of each path), then one sphere per point.
    start = Clip(registrationName="paths_theta0", Input=top)
    start.ClipType = "Scalar"
    start.Scalars = ["POINTS", "theta_deg"]
    start.Value = 1e-6
    start.Invert = 1
    glyph = Glyph(registrationName="paths_start", Input=start, GlyphType="Sphere")
    glyph.ScaleArray = ["POINTS", "No scale array"]
    glyph.ScaleFactor = 0.22
    glyph.GlyphMode = "All Points"
    dg = Show(glyph, view)
    solid(dg, BLACK)

    style_bar(lut, view, "Bz [mT]")
    text(view, "Probe paths over the magnet (magnet frame) for one mounting case,\n"
               "drawn on top of Bz on the sensing plane z = %.2f mm;\n"
               "black dots: probe positions at theta = 0; thin circle: nominal r0 = %.1f mm"
         % (z_s, R0_MM), size=13)
    view.OrientationAxesVisibility = 0   # top view: x to the right, y up
    axes_grid(view)
    top_camera(view, z_s + 1.0, 4.2)
    return view


def body_section(name, bodies, region, view, color, width):
    """The outline of one region of bodies.vtu on the plane y = 0: its cells, their outer surface, cut
    by the plane; moved 1 mm towards the camera (at -y) so it lies on top of the slice."""
    cells = Threshold(registrationName=name + "_cells", Input=bodies)
    cells.Scalars = ["CELLS", "region"]
    cells.LowerThreshold = region
    cells.UpperThreshold = region
    surf = ExtractSurface(registrationName=name + "_surface", Input=cells)
    cut = Slice(registrationName=name, Input=surf)
    cut.SliceType = "Plane"
    cut.SliceType.Origin = [0, 0, 0]
    cut.SliceType.Normal = [0, 1, 0]
    front = Transform(registrationName=name + "_front", Input=cut)
    front.Transform.Translate = [0, -1.0, 0]
    d = Show(front, view)
    solid(d, color)
    d.LineWidth = width
    return cut


def make_steel_parts_B(data, vmax):
    """abs(B) of the steel_parts study's steel cup on the axis plane y = 0."""
    view = new_view((1000, 860))
    sl = XMLImageDataReader(registrationName="slice_y0.vti",
                            FileName=[os.path.join(data, STEEL_CUP_REL, "slice_y0.vti")])
    sl.PointArrayStatus = ["B"]
    sl.UpdatePipeline()
    b = sl.GetDataInformation().GetBounds()
    absb = Calculator(registrationName="slice_absB_T", Input=sl)
    absb.ResultArrayName = "absB_T"
    absb.Function = "mag(B)"
    d = Show(absb, view)
    ColorBy(d, ("POINTS", "absB_T"))
    lut = GetColorTransferFunction("absB_T")
    lut.ApplyPreset("Turbo", True)   # many hues: 1 T (magnet) and 2 T (saturated steel) differ
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(*ABS_B_RANGE_T)
    lut.MapControlPointsToLogSpace()   # the preset's points spread evenly in log(abs(B)), as the GUI does
    lut.UseLogScale = 1
    d.LookupTable = lut
    bar = style_bar(lut, view, "abs(B) [T]", pos=(0.86, 0.12), length=0.6)
    bar.AddRangeLabels = 1
    bar.RangeLabelFormat = "%-#.3g"

    # B's direction: unit arrows on a coarse subset of the slice (every 12th node, 0.6 mm).
    sub = ExtractSubset(registrationName="slice_coarse", Input=sl)
    sub.SampleRateI, sub.SampleRateJ, sub.SampleRateK = 12, 1, 12
    unit = Calculator(registrationName="B_unit", Input=sub)
    unit.ResultArrayName = "B_dir"
    unit.Function = "B/mag(B)"
    arrows = Glyph(registrationName="B_arrows", Input=unit, GlyphType="Arrow")
    arrows.OrientationArray = ["POINTS", "B_dir"]
    arrows.ScaleArray = ["POINTS", "No scale array"]
    arrows.ScaleFactor = 0.42
    arrows.GlyphMode = "All Points"
    arrows.GlyphTransform.Translate = [-0.5, 0, 0]   # arrows centred on their node
    front = Transform(registrationName="B_arrows_front", Input=arrows)
    front.Transform.Translate = [0, -0.5, 0]
    da = Show(front, view)
    solid(da, [0.1, 0.1, 0.1])
    da.Opacity = 0.6

    bodies = XMLUnstructuredGridReader(registrationName="bodies.vtu",
                                       FileName=[os.path.join(data, STEEL_CUP_REL, "bodies.vtu")])
    bodies.CellArrayStatus = ["B", "region", "mu_r"]
    body_section("part_section", bodies, 10, view, WHITE, 4.0)
    body_section("magnet_section", bodies, 1, view, BLACK, 2.5)

    # The sensing plane (z = z_s) and the probes at +-r0 on it.
    z_s = plane_height_mm(data)
    line = Line(registrationName="sensing_plane", Point1=[b[0], -1.0, z_s], Point2=[b[1], -1.0, z_s])
    dl = Show(line, view)
    solid(dl, WHITE)
    dl.LineWidth = 2.5
    for k, x in enumerate((R0_MM, -R0_MM)):
        s = Sphere(registrationName="probe_at_%s_r0" % ("plus", "minus")[k], Center=[x, -1.5, z_s],
                   Radius=0.12, ThetaResolution=24, PhiResolution=24)
        solid(Show(s, view), WHITE)

    text(view, "abs(B) of the steel_parts study's steel cup (B-H curve) on the plane y = 0 through the axis\n"
               "(magnetization along +x; log colour scale). Cut outlines: black = magnet, white = cup;\n"
               "arrows: direction of B; white line: sensing plane z = %.2f mm, dots: probes at x = +-r0" % z_s,
         size=13)
    view.OrientationAxesVisibility = 0
    axes_grid(view, ytitle="", ztitle="z [mm]")
    zc = 0.5 * (b[4] + b[5])
    view.CameraParallelProjection = 1
    view.CameraPosition = [0.6, -60, zc]
    view.CameraFocalPoint = [0.6, 0, zc]
    view.CameraViewUp = [0, 0, 1]
    view.CameraParallelScale = 0.5 * (b[5] - b[4]) + 0.9
    return view


def plane_height_mm(data):
    """The sensing plane's z (mm) of the steel_parts run: magnet.height_mm / 2 + sensor.plane_height_mm
    from its config.toml (the values it used)."""
    cfg = open(os.path.join(data, "steel_parts", "config.toml")).read()
    sec = lambda name: cfg.split("[" + name + "]", 1)[1]
    num = lambda text, key: float(re.search(r"^\s*" + key + r"\s*=\s*([-0-9.eE+]+)", text, re.M).group(1))
    return 0.5 * num(sec("magnet"), "height_mm") + num(sec("sensor"), "plane_height_mm")


def save_relocatable(path, data):
    """SaveState, then store data file names as output/<sub>/<file>."""
    SaveState(path)
    with open(path) as f:
        s = f.read()
    absdata = os.path.abspath(data).rstrip("/")
    s = s.replace(absdata + "/", "output/")
    if absdata in s:
        raise SystemExit("make_states: an absolute data path is left in " + path)
    with open(path, "w") as f:
        f.write(s)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", required=True, help="output/ directory with field/ and " + PATHS_REL)
    ap.add_argument("--states", default=os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--only", default="", help="comma-separated state names (default: all)")
    a = ap.parse_args()
    data = os.path.abspath(a.data)
    states = (("plane_bz", make_plane_bz), ("magnet_field", make_magnet_field),
              ("probe_paths", make_probe_paths), ("steel_parts_B", make_steel_parts_B))
    only = [n for n in a.only.split(",") if n]
    unknown = [n for n in only if n not in dict(states)]
    if unknown:
        raise SystemExit("make_states: --only %s: allowed %s" % (",".join(unknown), ", ".join(dict(states))))
    states = [(n, f) for n, f in states if not only or n in only]
    vmax = 0.0
    if any(n != "steel_parts_B" for n, _ in states):
        vmax = plane_range_mT(data)
        vmax = nice_step(vmax / 4.0) * math.ceil(vmax / nice_step(vmax / 4.0))  # round up
    # paraview.simple resets the camera at the first Render of a process: spend it on a throwaway view,
    # so that every state keeps the camera its builder sets (with --only too).
    Render(CreateView("RenderView"))
    for name, build in states:
        ResetSession()
        view = build(data, vmax)
        SetActiveView(view)
        Render(view)
        out = os.path.join(a.states, name + ".pvsm")
        save_relocatable(out, data)
        print("make_states: wrote", out)


if __name__ == "__main__":
    main()
