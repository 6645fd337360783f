#!/usr/bin/env bash
# The package's type stubs (python/magenc/_magenc.pyi), with PYTHONPATH at a build tree's python/:
#   1. mypy --strict accepts python/checks/stubs_usage.py (and the usage runs);
#   2. mypy --strict rejects each of the 3 lines of python/checks/stubs_misuse.py (the stubs can fail);
#   3. mypy.stubtest finds every name of the stubs in the compiled module and no public name missing.
# Usage: check_stubs.sh PYTHON   (ctest python_stubs_mypy)
set -euo pipefail
py=$1
here=$(cd "$(dirname "$0")" && pwd)
cache=$(mktemp -d)
trap 'rm -rf "$cache"' EXIT
"$py" -m mypy --strict --cache-dir "$cache" "$here/stubs_usage.py"
"$py" "$here/stubs_usage.py" >/dev/null
set +e
out=$("$py" -m mypy --strict --cache-dir "$cache" "$here/stubs_misuse.py")
status=$?
set -e
errors=$(grep -c "stubs_misuse.py:[0-9]*: error" <<<"$out" || true)
if [ "$status" = 0 ] || [ "$errors" != 3 ]; then
  echo "mypy --strict should find 3 errors in stubs_misuse.py, found $errors:"; echo "$out"; exit 1
fi
"$py" -m mypy.stubtest --mypy-config-file /dev/null magenc
echo "stubs: usage accepted, 3 misuses rejected, stubtest clean"
