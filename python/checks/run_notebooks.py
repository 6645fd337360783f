"""Runs examples/*.ipynb with a real kernel (nbclient, ipykernel) and checks their numbers against the
executables' (ctest python_notebooks).

Each notebook ends with a cell tagged "results" that prints one JSON object; the numbers in it must equal
the executables' for the same keys: field_at's 17 digits bit for bit, the spectra tables' and
residual.json's 10 significant digits to a relative 1e-9 (the tables' rounding). A notebook that raises,
prints no results, or differs fails the test. Figures must be produced (an image/png output).
Usage: run_notebooks.py BIN_DIR EXAMPLES_DIR   (PYTHONPATH: a tree's python/ or an installed magenc)
"""
import csv
import io
import json
import math
import pathlib
import subprocess
import sys
import tempfile

import nbformat
from nbclient import NotebookClient

BIN, EXAMPLES = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
REL = 1e-9  # the tables print 10 significant digits
failures = []


def exe(name, *args, cwd=None):
    r = subprocess.run([str(BIN / name), *map(str, args)], capture_output=True, text=True, cwd=cwd)
    if r.returncode != 0:
        raise RuntimeError(f"{name} {' '.join(map(str, args))}: {r.stderr.strip()}")
    return r.stdout


def spectra_row(*args):
    rows = list(csv.DictReader(io.StringIO(exe("error_spectrum", *args))))
    assert len(rows) == 1, rows
    return {k: float(v) for k, v in rows[0].items() if k.endswith("_deg") and k[0] in "cp"}


def close(name, got, want):
    if not (abs(got - want) <= REL * max(abs(want), 1e-12)):
        failures.append(f"{name}: notebook {got!r}, executable {want!r}")


def same_spectrum(name, got, want):
    for k in ("c1_deg", "c2_deg", "c3_deg", "c4_deg", "pp_deg"):
        close(f"{name} {k}", got[k], want[k])


def check_field(res, tmp):
    (tmp / "p.csv").write_text("x_mm,y_mm,z_mm\n2.4,0,4.55\n")
    row = exe("field_at", "--points", tmp / "p.csv").strip().splitlines()[-1].split(",")
    if res["B_ref_T"] != [float(v) for v in row[3:6]]:
        failures.append(f"field: B_ref_T {res['B_ref_T']} != field_at's {row[3:6]}")


def check_error_curve(res, tmp):
    same_spectrum("two", res["two"], spectra_row("--array", "two", "--r0", "2.4", "--dx", "0.1"))
    same_spectrum("diff4", res["diff4"], spectra_row("--array", "diff4", "--r0", "2.4", "--dx", "0.1"))


RING = ["--set", "magnet.radius_mm=16", "--set", "magnet.inner_radius_mm=11", "--set", "magnet.height_mm=4",
        "--set", "magnet.br_T=1.2", "--sx", "0.05"]


def check_ring(res, tmp):
    side = spectra_row(*RING, "--principle", "inplane", "--array", "point", "--set", "sensor.center_mm=[18, 0]",
                       "--set", "sensor.plane_height_mm=-2", "--set", "sensor.direction=auto",
                       "--set", "sensor.zero_deg=auto")
    trim = ["--set", "sensor.gain_trim=auto"]
    side_trim = spectra_row(*RING, "--principle", "inplane", "--array", "point", "--set", "sensor.center_mm=[18, 0]",
                            "--set", "sensor.plane_height_mm=-2", "--set", "sensor.direction=auto",
                            "--set", "sensor.zero_deg=auto", *trim)
    bore = spectra_row(*RING, "--array", "diff4", "--r0", "13.5", "--set", "sensor.plane_height_mm=1")
    same_spectrum("side-shaft inplane", res["side-shaft inplane"], side)
    same_spectrum("side-shaft inplane, gain trim", res["side-shaft inplane, gain trim"], side_trim)
    same_spectrum("bore diff4", res["bore diff4"], bore)


def check_calibration(res, tmp):
    exe("calibrate", "--method", "harmonics:8", "--apply", "run", "--set", "mount.sx_mm=0.1",
        "--set", "mount.dx_mm=0.12",
        "--set", "mount.dz_mm=0.05", "--out", tmp / "cal")
    want = json.loads((tmp / "cal" / "residual.json").read_text())
    numbers = [k for k, v in want.items() if isinstance(v, (int, float))]
    if not numbers:
        failures.append("calibration: residual.json has no numbers")
    for k in numbers:
        close(f"calibration {k}", res[k], want[k])


CHECKS = {"field": check_field, "error_curve": check_error_curve, "ring_side_vs_bore": check_ring,
          "calibration": check_calibration}

found = sorted(p.stem for p in EXAMPLES.glob("*.ipynb"))
if found != sorted(CHECKS):
    failures.append(f"notebooks {found}, checks for {sorted(CHECKS)}: every notebook needs its check")
for stem in sorted(set(found) & set(CHECKS)):
    with tempfile.TemporaryDirectory() as d:
        tmp = pathlib.Path(d)
        nb = nbformat.read(EXAMPLES / f"{stem}.ipynb", as_version=4)
        NotebookClient(nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": d}}).execute()
        tagged = [c for c in nb.cells if "results" in c.get("metadata", {}).get("tags", [])]
        text = "".join(o.get("text", "") for c in tagged for o in c.get("outputs", []) if o.get("name") == "stdout")
        pngs = sum("image/png" in o.get("data", {}) for c in nb.cells if c.cell_type == "code" for o in c.outputs)
        if len(tagged) != 1 or not text.strip():
            failures.append(f"{stem}: no printed results cell")
            continue
        if pngs == 0:
            failures.append(f"{stem}: no figure")
        CHECKS[stem](json.loads(text), tmp)
        print(f"{stem}: ran, {pngs} figure(s), numbers equal the executables'")

if failures:
    print("\n".join(failures))
    sys.exit(1)
