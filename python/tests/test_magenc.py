"""The Python module against the executables: same numbers for the same inputs, bad input raises."""
import csv
import io
import json
import math
import pathlib

import numpy as np
import pytest

import magenc


def read_csv(text):
    rows = list(csv.DictReader(io.StringIO(text)))
    assert rows, "empty table"
    return rows


# ---- field_at ----

MAGNET = {"magnet.radius_mm": 3.0, "magnet.height_mm": 5.0, "magnet.magnetization_deg": 40.0,
          "magnet.magnetization_elevation_deg": -35.0, "magnet.br_T": 1.35}


def test_field_at_equals_the_executable_to_the_last_bit(tmp_path, run_exe):
    rng = np.random.default_rng(7)
    pts = rng.uniform(-8, 8, size=(50, 3))
    pts[:5] = rng.uniform(-1, 1, size=(5, 3))  # inside the magnet too
    f = tmp_path / "pts.csv"
    f.write_text("x_mm,y_mm,z_mm\n" + "".join(f"{x:.17g},{y:.17g},{z:.17g}\n" for x, y, z in pts))
    sets = [a for k, v in MAGNET.items() for a in ("--set", f"{k}={v!r}")]
    r = run_exe("field_at", "--points", f, *sets)
    assert r.returncode == 0, r.stderr
    rows = read_csv(r.stdout)
    exe = np.array([[float(row[c]) for c in ("Bx_T", "By_T", "Bz_T")] for row in rows])
    B = magenc.field_at(pts, config=MAGNET)
    assert B.shape == (50, 3) and B.dtype == np.float64
    np.testing.assert_array_equal(B, exe)
    # keyword arguments are the same keys
    kw = {k.replace(".", "_", 1): v for k, v in MAGNET.items()}
    np.testing.assert_array_equal(magenc.field_at(pts, **kw), exe)


def test_field_at_one_point_and_physics_sanity():
    # default magnet (R 2, L 4, Br 1.2 T, diametric along x): at the centre B = Br - demagnetizing field
    B = magenc.field_at([0.0, 0.0, 0.0])
    assert B.shape == (1, 3)
    assert 0.5 < B[0, 0] < 1.2 and abs(B[0, 1]) < 1e-15 and abs(B[0, 2]) < 1e-15
    # closed form on the axis of an axially magnetized cylinder (docs/field_at.md)
    R, L, Br, z = 2.0, 4.0, 1.2, 3.1
    Bz = Br / 2 * ((z + L / 2) / math.hypot(R, z + L / 2) - (z - L / 2) / math.hypot(R, z - L / 2))
    B = magenc.field_at([[0, 0, z]], magnet_magnetization_elevation_deg=90)
    assert B[0, 2] == pytest.approx(Bz, rel=1e-13)


def test_field_at_of_a_multipole_ring_equals_the_executable_and_repeats_with_the_pole_pitch(tmp_path, run_exe):
    ring = {"magnet.pattern": "axial_multipole", "magnet.pole_pairs": 8, "magnet.inner_radius_mm": 3.0,
            "magnet.radius_mm": 6.0, "magnet.height_mm": 1.5, "magnet.br_T": 0.3}
    phi = np.linspace(0.0, 2 * math.pi / 8, 7)
    pts = np.stack([4.5 * np.cos(phi), 4.5 * np.sin(phi), np.full_like(phi, 1.2)], axis=1)
    f = tmp_path / "pts.csv"
    f.write_text("x_mm,y_mm,z_mm\n" + "".join(f"{x:.17g},{y:.17g},{z:.17g}\n" for x, y, z in pts))
    sets = [a for k, v in ring.items() for a in ("--set", f"{k}={v!r}")]
    r = run_exe("field_at", "--points", f, *sets)
    assert r.returncode == 0, r.stderr
    exe = np.array([[float(row[c]) for c in ("Bx_T", "By_T", "Bz_T")] for row in read_csv(r.stdout)])
    B = magenc.field_at(pts, config=ring)
    np.testing.assert_array_equal(B, exe)
    # one pole pair on: the same Bz; half of it: the opposite (a north pole becomes a south pole)
    assert B[-1, 2] == pytest.approx(B[0, 2], rel=1e-12)
    assert B[3, 2] == pytest.approx(-B[0, 2], rel=1e-12)
    assert abs(B[0, 2]) > 0.01


def test_field_at_refuses_what_the_executable_refuses(tmp_path, run_exe):
    f = tmp_path / "pts.csv"
    f.write_text("x_mm,y_mm,z_mm\n0,0,5\n0.5,0.5,2\n")
    r = run_exe("field_at", "--points", f)
    assert r.returncode == 2
    with pytest.raises(ValueError) as e:
        magenc.field_at([[0, 0, 5], [0.5, 0.5, 2]])
    assert str(e.value) in r.stderr  # the same one-line message
    assert "point 2" in str(e.value) and "surface" in str(e.value)
    with pytest.raises(ValueError, match="not finite"):
        magenc.field_at([[0, 0, math.nan]])
    with pytest.raises(ValueError, match=r"allowed \(N, 3\)"):
        magenc.field_at(np.zeros((4, 2)))
    with pytest.raises(ValueError, match="mesh.vtu does not exist"):
        magenc.field_at([[0, 0, 5]], field="fem:" + str(tmp_path / "no_such_solve"))


# ---- configuration ----

def test_unknown_key_and_bad_value_raise_the_executables_message(run_exe, tmp_path):
    f = tmp_path / "pts.csv"
    f.write_text("x_mm,y_mm,z_mm\n0,0,5\n")
    r = run_exe("field_at", "--points", f, "--set", "magnet.colour=1")
    assert r.returncode == 2
    with pytest.raises(ValueError) as e:
        magenc.field_at([[0, 0, 5]], config={"magnet.colour": 1})
    assert str(e.value) in r.stderr
    r = run_exe("field_at", "--points", f, "--set", "magnet.radius_mm=-1")
    with pytest.raises(ValueError) as e:
        magenc.field_at([[0, 0, 5]], magnet_radius_mm=-1)
    assert str(e.value) in r.stderr
    with pytest.raises(ValueError, match="unknown configuration keyword 'radius'"):
        magenc.field_at([[0, 0, 5]], radius=1)
    with pytest.raises(ValueError, match="must be a dict"):
        magenc.angle_error(config=[("mount.sx_mm", 1)])


def test_config_keys_lists_every_key_with_its_range():
    keys = {k["key"]: k for k in magenc.config_keys()}
    assert keys["mount.sx_mm"]["unit"] == "mm"
    assert "magnet.magnetization_elevation_deg" in keys
    assert keys["sensor.array"]["default"] == "two"


# ---- angle error and spectrum ----

CASES = [
    ("two", {"mount.dx_mm": 0.1, "mount.sx_mm": 0.05}),
    ("diff4", {"mount.sy_mm": 0.08, "mount.dz_mm": 0.2, "mount.tilt_x_deg": 1.0,
               "magnet.magnetization_elevation_deg": 3.0}),
    ("ring:6", {"mount.dy_mm": 0.05, "sensor.r0_mm": 2.0, "sensor.steps": 720, "sensor.gain_mismatch": 0.01}),
    # a turning encoder (docs/physics.md "Speed"): delay, skew, filter, ideal prediction and a hold
    ("two", {"mount.dx_mm": 0.1, "speed.rpm": 6000.0, "sensor.delay_us": 96.0, "sensor.skew_us": 2.0,
             "sensor.filter_hz": 1000.0, "sensor.sample_hz": 7777.0, "sensor.prediction": "ideal"}),
]


@pytest.mark.parametrize("array,keys", CASES)
def test_angle_error_spectrum_equals_error_spectrum(array, keys, run_exe):
    sets = [a for k, v in keys.items() for a in ("--set", f"{k}={v!r}")]
    r = run_exe("error_spectrum", "--field", "analytic", "--array", array, *sets)
    assert r.returncode == 0, r.stderr
    row = read_csv(r.stdout)[0]
    theta, eps = magenc.angle_error(array=array, config=keys)
    steps = keys.get("sensor.steps", 3600)
    assert theta.shape == (steps,) and eps.shape == (steps,)
    np.testing.assert_allclose(theta, 360.0 * np.arange(steps) / steps, rtol=0, atol=1e-12)
    s = magenc.spectrum(eps)
    assert list(s) == [f"a{n}_deg" for n in range(9)] + [f"b{n}_deg" for n in range(1, 9)] + \
        [f"c{n}_deg" for n in range(1, 9)] + ["pp_deg"]
    for name, value in s.items():
        # the table prints 10 significant digits
        assert value == pytest.approx(float(row[name]), rel=1e-9, abs=1e-15), name
    assert s["c1_deg"] > 0


def test_spectrum_of_a_known_series():
    m = 720
    theta = np.arange(m) * 2 * np.pi / m
    eps = 0.1 + 0.3 * np.cos(theta) - 0.2 * np.sin(2 * theta) + 0.05 * np.cos(8 * theta)
    s = magenc.spectrum(eps)
    assert s["a0_deg"] == pytest.approx(0.1, abs=1e-15)
    assert s["a1_deg"] == pytest.approx(0.3, abs=1e-15)
    assert s["b2_deg"] == pytest.approx(-0.2, abs=1e-15)
    assert s["c8_deg"] == pytest.approx(0.05, abs=1e-15)
    assert s["pp_deg"] == pytest.approx(eps.max() - eps.min(), abs=1e-15)
    with pytest.raises(ValueError, match="M >= 17"):
        magenc.spectrum(np.zeros(10))
    with pytest.raises(ValueError, match="not finite"):
        magenc.spectrum(np.r_[np.zeros(20), np.inf])


def test_spectrum_of_a_multipole_read_has_the_ce_columns_of_error_spectrum(run_exe):
    ring = {"magnet.pattern": "axial_multipole", "magnet.pole_pairs": 8, "magnet.inner_radius_mm": 3.0,
            "magnet.radius_mm": 6.0, "magnet.height_mm": 1.5, "magnet.br_T": 0.3, "sensor.r0_mm": 4.5,
            "sensor.plane_height_mm": 0.4, "sensor.steps": 360, "mount.dx_mm": 0.05}
    sets = [a for k, v in ring.items() for a in ("--set", f"{k}={v!r}")]
    r = run_exe("error_spectrum", "--field", "analytic", "--array", "two", *sets)
    assert r.returncode == 0, r.stderr
    row = read_csv(r.stdout)[0]
    _, eps = magenc.angle_error(array="two", config=ring)
    s = magenc.spectrum(eps, pole_pairs=8)
    assert [k for k in s if k.startswith("ce")] == ["ce1_deg", "ce2_deg", "ce3_deg", "ce4_deg"]
    for name, value in s.items():
        assert value == pytest.approx(float(row[name]), rel=1e-9, abs=1e-15), name
    assert s["ce4_deg"] > 1e-3  # the square wave's 3rd harmonic at order 4p
    assert "ce1_deg" not in magenc.spectrum(eps)
    with pytest.raises(ValueError, match="pole_pairs = -1"):
        magenc.spectrum(eps, pole_pairs=-1)


# ---- diagnose ----

def test_diagnose_equals_the_executable_and_recovers_the_truth(tmp_path, run_exe):
    truth = {"mount.sx_mm": 0.04, "mount.dx_mm": 0.06}
    theta, eps = magenc.angle_error(config=dict(truth, **{"sensor.steps": 360}))
    curve = tmp_path / "curve.csv"
    curve.write_text("theta_deg,error_deg\n" + "".join(f"{t:.17g},{e:.17g}\n" for t, e in zip(theta, eps)))
    fit = magenc.diagnose(curve, free=["sx", "dx"], starts=2)
    r = run_exe("diagnose", "--measured", curve, "--field", "analytic", "--array", "two", "--r0", "2.4",
                "--free", "sx,dx", "--starts", "2", "--out", tmp_path / "out")
    assert r.returncode == 0, r.stderr
    exe = json.loads((tmp_path / "out" / "fit.json").read_text())
    assert set(fit["parameters"]) == set(exe["parameters"])
    for name, p in exe["parameters"].items():
        assert fit["parameters"][name]["free"] == p["free"]
        assert fit["parameters"][name]["value"] == pytest.approx(p["value"], rel=1e-9, abs=1e-12), name
    assert fit["residual_rms_deg"] == pytest.approx(exe["residual_rms_deg"], rel=1e-6, abs=1e-12)
    assert fit["parameters"]["sx_mm"]["value"] == pytest.approx(0.04, abs=1e-6)
    assert fit["parameters"]["dx_mm"]["value"] == pytest.approx(0.06, abs=1e-6)
    with pytest.raises(ValueError, match="nosuch"):
        magenc.diagnose(curve, free="nosuch")
    with pytest.raises(ValueError):
        magenc.diagnose(tmp_path / "missing.csv")
    assert fit["converged"] is True and fit["converged"] == exe["converged"]
    assert fit["explained_fraction"] == pytest.approx(exe["explained_fraction"], abs=1e-9)


def test_diagnose_raises_on_a_fit_that_explains_nothing(tmp_path):
    # A 0.5 deg 7th harmonic: no offset of `two` makes one; the executable exits 3, the module raises.
    curve = tmp_path / "h7.csv"
    curve.write_text("theta_deg,error_deg\n" + "".join(
        f"{2.0 * i:.17g},{0.5 * math.sin(7 * math.radians(2.0 * i)):.17g}\n" for i in range(180)))
    with pytest.raises(magenc.ComputeError, match="in harmonics 1..8"):
        magenc.diagnose(curve, free=["sx", "sy", "dx", "dy"], starts=2)


# ---- inspect ----

def rot(axis, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return {"x": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
            "y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            "z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


def test_inspect_equals_the_executable_and_recovers_the_truth(tmp_path, run_exe):
    # truth: offset (0.05, -0.03, 0.08) mm, rotations (1, -0.5, 2) deg, Br 1.17 T, direction (3, 2) deg
    g = np.arange(-3.0, 3.5, 1.0)
    p = np.array([[x, y, z] for z in (4.55, 5.55) for x in g for y in g])
    B = magenc.field_at(p + [0.05, -0.03, 0.08], magnet_br_T=1.17, magnet_magnetization_deg=3.0,
                        magnet_magnetization_elevation_deg=2.0)
    R = rot("z", 2.0) @ rot("y", -0.5) @ rot("x", 1.0)
    readings = B @ R  # rows: R^T b
    readings += np.random.default_rng(3).normal(0.0, 0.05e-3, readings.shape)
    scan = tmp_path / "scan.csv"
    np.savetxt(scan, np.column_stack([p, 1e3 * readings]), delimiter=",", fmt="%.12g",
               header="x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT", comments="")
    fit = magenc.inspect(scan, free="offset,rotation,polarization,direction")
    r = run_exe("inspect", "--scan", scan, "--free", "offset,rotation,polarization,direction",
                "--out", tmp_path / "out")
    assert r.returncode == 0, r.stderr
    exe = json.loads((tmp_path / "out" / "fit.json").read_text())
    truth = {"offset_x_mm": 0.05, "offset_y_mm": -0.03, "offset_z_mm": 0.08, "rot_x_deg": 1.0,
             "rot_y_deg": -0.5, "rot_z_deg": 2.0, "polarization_T": 1.17, "magnetization_deg": 3.0,
             "magnetization_elevation_deg": 2.0}
    for name, t in truth.items():
        e, f = exe["parameters"][name], fit["parameters"][name]
        assert f["value"] == pytest.approx(e["value"], rel=1e-9, abs=1e-12), name
        assert f["sigma"] == pytest.approx(e["sigma"], rel=1e-6), name
        assert abs(f["value"] - t) < 4 * f["sigma"], name
    assert fit["residual_rms_mT"] == pytest.approx(0.05, rel=0.2)
    with pytest.raises(ValueError, match="not a parameter group"):
        magenc.inspect(scan, free=["tilt"])


# ---- fem:DIR ----

def test_fem_source_equals_the_executable_to_the_last_bit(tmp_path, run_exe):
    """A coarse solve_field output read as fem:DIR: B at points and one mounting case, module vs executables."""
    root = pathlib.Path(__file__).resolve().parents[2]
    solve = tmp_path / "field"
    r = run_exe("solve_field", "--config", root / "meshes" / "coarse.toml", "--set", "output.mesh_vtu=true",
                "--out", solve)
    assert r.returncode == 0, r.stderr
    rng = np.random.default_rng(11)
    pts = np.column_stack([rng.uniform(-3, 3, 20), rng.uniform(-3, 3, 20), rng.uniform(4.2, 4.9, 20)])
    f = tmp_path / "pts.csv"
    f.write_text("x_mm,y_mm,z_mm\n" + "".join(f"{x:.17g},{y:.17g},{z:.17g}\n" for x, y, z in pts))
    r = run_exe("field_at", "--field", f"fem:{solve}", "--points", f)
    assert r.returncode == 0, r.stderr
    exe = np.array([[float(row[c]) for c in ("Bx_T", "By_T", "Bz_T")] for row in read_csv(r.stdout)])
    B = magenc.field_at(pts, field=f"fem:{solve}")
    np.testing.assert_array_equal(B, exe)
    # the FE field of the default magnet (mu_r 1.05, coarse mesh) is the exact field within a few % of its peak
    exact = magenc.field_at(pts)
    assert np.max(np.abs(B - exact)) < 0.05 * np.max(np.abs(exact))
    # the same mount through the FE field: the spectrum equals error_spectrum's to its printed digits
    r = run_exe("error_spectrum", "--field", f"fem:{solve}", "--array", "two", "--r0", "2.4", "--dx", "0.1",
                "--steps", "360")
    assert r.returncode == 0, r.stderr
    row = read_csv(r.stdout)[0]
    theta, eps = magenc.angle_error(field=f"fem:{solve}", array="two", mount_dx_mm=0.1, sensor_steps=360)
    spec = magenc.spectrum(eps)
    for n in (1, 2, 3, 4):
        assert spec[f"c{n}_deg"] == pytest.approx(float(row[f"c{n}_deg"]), rel=1e-8, abs=1e-10)


# ---- calibrate ----

def test_calibrate_equals_the_executable(tmp_path, run_exe):
    # the simulated calibration state at the default calibration.at, applied to a re-mounted run state
    keys = {"mount.sx_mm": 0.05, "mount.dx_mm": 0.08, "sensor.steps": 720}
    got = magenc.calibrate(method="harmonics:4", apply="run", config=keys)
    sets = [a for k, v in keys.items() for a in ("--set", f"{k}={v!r}")]
    r = run_exe("calibrate", "--method", "harmonics:4", "--apply", "run", *sets, "--out", tmp_path / "out")
    assert r.returncode == 0, r.stderr
    corr = json.loads((tmp_path / "out" / "correction.json").read_text())
    res = json.loads((tmp_path / "out" / "residual.json").read_text())
    assert got["source"] == "simulated calibration.at"
    assert got["correction"] == corr
    for k, v in res.items():
        assert got["residual"][k] == v, k
    rows = read_csv((tmp_path / "out" / "residual.csv").read_text())
    for col in ("theta_deg", "error_deg", "residual_deg"):
        np.testing.assert_allclose(got["residual"][col], [float(row[col]) for row in rows], rtol=1e-9, atol=1e-12)
    # the correction removes what it was fitted to: at the calibration state itself the residual is small
    own = magenc.calibrate(method="harmonics:8", apply="run",
                           config={"mount.sx_mm": 0.1, "mount.dx_mm": 0.1, "sensor.steps": 720})
    assert own["residual"]["pp_after_deg"] < 1e-2 * own["residual"]["pp_before_deg"]


def test_calibrate_from_a_measured_curve_and_bad_input(tmp_path):
    theta, eps = magenc.angle_error(config={"mount.sx_mm": 0.1, "sensor.steps": 360})
    curve = tmp_path / "curve.csv"
    curve.write_text("theta_deg,error_deg\n" + "".join(f"{t:.17g},{e:.17g}\n" for t, e in zip(theta, eps)))
    got = magenc.calibrate(measured=curve, method="lut:64", apply=curve)
    assert got["source"] == str(curve)
    assert got["residual"]["pp_after_deg"] < 0.05 * got["residual"]["pp_before_deg"]
    with pytest.raises(ValueError, match="both give the correction"):
        magenc.calibrate(measured=curve, correction=curve)
    with pytest.raises(ValueError, match="method = none"):
        magenc.calibrate(measured=curve)
    with pytest.raises(ValueError, match="ogp needs the raw channels"):
        magenc.calibrate(measured=curve, method="ogp")


# ---- rings and sensors off the axis ----
def test_side_shaft_ring_keys_pass_through_and_give_the_reference_ellipse():
    # docs/physics.md "Ring magnets and sensors off the axis": k 4.19468, pp 75.9024 deg (6 digits printed).
    ring = dict(magnet_radius_mm=16, magnet_inner_radius_mm=11, magnet_height_mm=4, magnet_br_T=1.2)
    side = dict(sensor_principle="inplane", sensor_center_mm=[18, 0], sensor_plane_height_mm=-2)
    theta, eps = magenc.angle_error(**ring, **side, sensor_direction=-1, sensor_zero_deg=180)
    assert abs((eps.max() - eps.min()) - 75.9024) <= 0.5e-4
    # direction and zero found on the nominal mount, the gain trimmed: the ellipse is gone.
    theta, eps = magenc.angle_error(**ring, **side, sensor_direction="auto", sensor_zero_deg="auto",
                                    sensor_gain_trim="auto")
    assert eps.max() - eps.min() < 1e-9
    # the ring's field in its bore: B along M, no mu0 M (the bore is air)
    B = magenc.field_at(np.array([[0.0, 0.0, 0.0]]), **ring)
    S = lambda a: 2 * 2 / math.hypot(a, 2)  # (z + L/2)/s+ - (z - L/2)/s- at z = 0
    assert B[0, 0] == pytest.approx(-1.2 / 4 * (S(16) - S(11)), rel=1e-12)


def test_off_axis_bad_input_raises_one_line():
    with pytest.raises(ValueError, match="magnet.inner_radius_mm"):
        magenc.field_at(np.array([[0.0, 0.0, 9.0]]), magnet_radius_mm=4, magnet_inner_radius_mm=4)
    with pytest.raises(ValueError, match="sensor.center_mm"):
        magenc.angle_error(magnet_radius_mm=16, magnet_inner_radius_mm=11, magnet_height_mm=4,
                           sensor_principle="inplane", sensor_center_mm=[13, 0], sensor_plane_height_mm=-2)
    with pytest.raises(ValueError, match="sensor.direction"):
        magenc.angle_error(sensor_direction=2)


# ---- hostile arguments: one line, the argument named ----
def one_line(excinfo):
    return "\n" not in str(excinfo.value)


def test_points_must_be_real_numbers():
    for bad, word in (([[1 + 2j, 0, 4.55]], "complex"), (np.array([[True, False, True]]), "bools"),
                      ([["0.1", "0", "4.55"]], "text")):
        with pytest.raises(ValueError, match=word) as e:
            magenc.field_at(bad)
        assert one_line(e)
    # ints are real numbers
    assert magenc.field_at([[0, 0, 5]]).shape == (1, 3)


def test_config_values_are_of_the_key_type():
    for value, word in (("0.1", "is a str: allowed a number"), (np.bool_(True), "mount.sx_mm"),
                        (10**30, "mount.sx_mm"), (1 + 1j, "complex"), ("a\nb", None)):
        with pytest.raises(ValueError, match=word) as e:
            magenc.angle_error(config={"mount.sx_mm": value, "sensor.steps": 64})
        assert one_line(e)
    with pytest.raises(ValueError, match="line break") as e:
        magenc.angle_error(config={"sensor.array": "two\ndiff4"})
    assert one_line(e)
    # numpy numbers that are real are numbers
    a = magenc.angle_error(config={"mount.sx_mm": np.float64(0.1), "sensor.steps": np.int64(64)})
    b = magenc.angle_error(config={"mount.sx_mm": 0.1, "sensor.steps": 64})
    assert np.array_equal(a[1], b[1])


def test_dict_valued_keys_are_toml_tables():
    # calibration.at as a dict equals its TOML text
    d = magenc.calibrate(method="harmonics:4", apply="run", config={"calibration.at": {"mount.sx_mm": 0.1}})
    t = magenc.calibrate(method="harmonics:4", apply="run", config={"calibration.at": "{mount.sx_mm = 0.1}"})
    assert d["correction"] == t["correction"]
    assert d["residual"]["pp_after_deg"] == t["residual"]["pp_after_deg"]
    with pytest.raises(ValueError, match="calibration.at") as e:
        magenc.calibrate(method="harmonics:4", config={"calibration.at": {"mount.nope": 1}})
    assert one_line(e)


def test_function_arguments_are_checked_by_name():
    for kwargs, exc, word in ((dict(interp=None), TypeError, "interp = None is not a str"),
                              (dict(field=5), TypeError, "field = 5 is not a str")):
        with pytest.raises(exc, match=word) as e:
            magenc.field_at([[0, 0, 5]], **kwargs)
        assert one_line(e)
    with pytest.raises(ValueError, match=r"seed = -1 is out of range") as e:
        magenc.diagnose("x.csv", seed=-1)
    assert one_line(e)
    with pytest.raises(ValueError, match="starts = 10000000000000000000000000000000 is out of range") as e:
        magenc.diagnose("x.csv", starts=10**31)
    assert one_line(e)
    with pytest.raises(TypeError, match="fixed_zero = 'yes' is not a bool") as e:
        magenc.diagnose("x.csv", fixed_zero="yes")
    assert one_line(e)
    with pytest.raises(TypeError, match="cond_limit = '1e6' is not a real number") as e:
        magenc.inspect("x.csv", cond_limit="1e6")
    assert one_line(e)
