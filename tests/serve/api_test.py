"""serve's what-if API without a browser (ctest serve_api): the numbers equal error_spectrum's; every bad
input is status 400 with a one-line message naming the key, and the server keeps answering.
Usage: api_test.py BIN_DIR
"""
import csv
import io
import json
import pathlib
import subprocess
import sys
import urllib.error
import urllib.request

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from serve_process import running_serve  # noqa: E402

BIN = pathlib.Path(sys.argv[1])


def post(url, body):
    try:
        with urllib.request.urlopen(url + "api/whatif", body.encode(), timeout=30) as r:
            return r.status, json.loads(r.read())
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read())


def spectra(*args):
    r = subprocess.run([str(BIN / "error_spectrum"), *args], capture_output=True, text=True, check=True)
    return list(csv.DictReader(io.StringIO(r.stdout)))[0]


with running_serve(BIN / "serve") as url:
    cases = [("mount.dx_mm=0.1\nsensor.array=diff4\nmount.sx_mm=0.2",
              ["--dx", "0.1", "--array", "diff4", "--sx", "0.2"]),
             ("magnet.inner_radius_mm=1\nsensor.principle=inplane\nsensor.array=point\nmount.dy_mm=0.05\n"
              "speed.rpm=3000",
              ["--set", "magnet.inner_radius_mm=1", "--principle", "inplane", "--array", "point", "--dy", "0.05",
               "--set", "speed.rpm=3000"]),
             ("stray.uniform_mT=1,0,0\nsensor.field_min_mT=40", ["--set", "stray.uniform_mT=1,0,0",
                                                                 "--set", "sensor.field_min_mT=40"])]
    for body, args in cases:
        status, r = post(url, body)
        assert status == 200 and r["ok"], (body, r)
        want = spectra(*args)
        for k, v in r["spectrum"].items():
            w = float(want[k])
            assert abs(v - w) <= 1e-9 * max(abs(w), 1e-12), f"{body!r}: {k} {v!r} != error_spectrum's {w!r}"
        assert abs(r["field_min_mT"] - float(want["field_min_mT"])) <= 1e-9 * abs(float(want["field_min_mT"]))
        assert r["in_window"] == (want["in_window"] == "1"), (body, r["in_window"], want["in_window"])
        assert len(r["theta_deg"]) == len(r["eps_deg"]) == 3600 and r["map"]["n"] ** 2 == len(r["map"]["value_mT"])
    bad = {"mount.dx_mm=abc": "mount.dx_mm", "mount.sx=1": "mount.sx", "sensor.steps=3": "sensor.steps",
           "sensor.array=ring:2": "sensor.array", "magnet.inner_radius_mm=5": "inner_radius",
           "no equals sign": "no equals sign", "sensor.principle=inplane\nsensor.array=diff4": "array",
           "mount.tilt_x_deg=90": "mount.tilt_x_deg", "\x00\xff=1": "",
           "calibration.method=lut:1": "calibration.method",
           "sensor.steps=200000": "sensor.steps"}
    for body, names in bad.items():
        status, r = post(url, body)
        assert status == 400 and r["ok"] is False, (body, status, str(r)[:300])
        assert "\n" not in r["error"] and names in r["error"], (body, r["error"])
    status, r = post(url, "sensor.plane_height_mm=0")  # the map's plane is the magnet's face: no map, named
    assert status == 200 and r["map"] is None and "field map" in r["map_error"], r
    try:  # a body over 64 KiB is refused before it is read
        urllib.request.urlopen(url + "api/whatif", b"mount.dx_mm=0.1\n" * 5000, timeout=30)
        raise AssertionError("a 80 KB body was accepted")
    except urllib.error.HTTPError as e:
        assert e.code == 413, e.code
    status, r = post(url, "")
    assert status == 200 and r["ok"], "the server stops answering after bad input"
    # bad command lines: a port in use, a bad key; one line, exit 2, nothing listening
    port = url.rstrip("/").rsplit(":", 1)[1]
    for args, name in ((["--port", port], "--port"), (["--set", "mount.dx_mm=x"], "mount.dx_mm"),
                       (["--port", "70000"], "--port")):
        r = subprocess.run([str(BIN / "serve"), *args], capture_output=True, text=True, timeout=30)
        lines = r.stderr.strip().splitlines()
        assert r.returncode == 2 and len(lines) == 1 and name in lines[0], (args, r.returncode, r.stderr)
print("serve API: numbers equal error_spectrum's; bad input answered with one line; the server keeps running")
