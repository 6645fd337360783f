"""Shared fixtures: where the executables are (MAGENC_BIN_DIR, set by ctest; default build/bin)."""
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def bin_dir():
    d = pathlib.Path(os.environ.get("MAGENC_BIN_DIR", ROOT / "build" / "bin"))
    return d


@pytest.fixture
def run_exe(bin_dir):
    """Runs build/bin/NAME with args; returns the CompletedProcess (text)."""

    def run(name, *args, cwd=None):
        exe = bin_dir / name
        if not exe.exists():
            pytest.fail(f"{exe} is not built: build the executables first (scripts/build.sh)")
        return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, cwd=cwd)

    return run
