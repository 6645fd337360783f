#!/usr/bin/env bash
# `pip install .` into a throwaway venv (--system-site-packages: Debian's numpy, setuptools, wheel), without
# network (--no-index), then `import magenc` from another folder without PYTHONPATH: the package must come
# from the venv and print the reference field of the field_at executable at (2.4, 0, 4.55) mm.
# The sources are a copy of what pip needs with MAGENC_BUILD_DIR (pyproject.toml, setup.py, README.md,
# python/); the compiled module comes from BUILD (setup.py only brings the target up to date), so the test
# costs seconds, not a compile. A build from scratch (no MAGENC_BUILD_DIR) configures the whole project.
# Usage: pip_install.sh SOURCE_DIR BUILD_DIR PYTHON   (ctest python_pip_install)
set -euo pipefail
src=$1 build=$2 py=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir "$tmp/src" "$tmp/elsewhere"
cp "$src/pyproject.toml" "$src/setup.py" "$src/README.md" "$tmp/src/"
cp -r "$src/python" "$tmp/src/python"
"$py" -m venv --system-site-packages --without-pip "$tmp/venv"
unset PYTHONPATH
MAGENC_BUILD_DIR="$build" "$tmp/venv/bin/python" -m pip install -q --no-index --no-build-isolation "$tmp/src"
rm -rf "$tmp/src"   # nothing may point back into the sources
cd "$tmp/elsewhere"
printf 'x_mm,y_mm,z_mm\n2.4,0,4.55\n' > p.csv
exe=$("$build/bin/field_at" --points p.csv | tail -1)
"$tmp/venv/bin/python" - "$tmp/venv" "$exe" <<'PY'
import pathlib, sys
import magenc
venv, exe = pathlib.Path(sys.argv[1]).resolve(), sys.argv[2]
where = pathlib.Path(magenc.__file__).resolve()
assert venv in where.parents, f"magenc imported from {where}, not from the venv {venv}"
for f in ("py.typed", "_magenc.pyi"):
    assert (where.parent / f).exists(), f"{f} not installed"
B = magenc.field_at([[2.4, 0, 4.55]])
ref = [float(v) for v in exe.split(",")[3:6]]
assert B.tolist() == [ref], f"field {B.tolist()} differs from field_at's {ref}"
print("installed in", where.parent, "B (T) =", B)
PY
