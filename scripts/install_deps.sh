#!/usr/bin/env bash
# Installs the Debian 12 packages magenc needs, only those that are missing.
# Runs as root on a fresh machine (as ./run.sh and ./test.sh do); idempotent.
# --with-getdp: also getdp and gmsh, used only by scripts/bench_getdp.sh (the
# GetDP comparison benchmark; not needed by ./run.sh or ./test.sh).
set -euo pipefail
with_getdp=0
for a in "$@"; do
  case "$a" in
    --with-getdp) with_getdp=1 ;;
    *) echo "install_deps.sh: unknown argument $a (allowed --with-getdp)" >&2; exit 2 ;;
  esac
done
PKGS=(
  build-essential cmake pkg-config
  libeigen3-dev            # linear algebra, sparse solvers
  libsleef-dev             # SLEEF: vectorized atan2 (the Monte Carlo engine, core/vector_math.hpp)
  libomp-dev               # OpenMP (g++ uses libgomp; kept for clang builds)
  libvtk9-dev              # VTK XML writers/readers
  libtet1.5-dev            # TetGen tetrahedral mesher
  catch2                   # unit tests (2.13)
  libcli11-dev             # command-line parsing
  libtomlplusplus-dev      # TOML configuration
  nlohmann-json3-dev       # JSON (solve.json)
  libbenchmark-dev         # Google Benchmark (bench target)
  gnuplot-nox              # plots (PNG via pngcairo)
  libceres-dev             # Ceres Solver: nonlinear least squares (diagnose)
  libfftw3-dev             # FFTW 3: the Monte Carlo engine's fixed-size transforms (src/probe/trig_interpolation.cpp)
  clang-14 libclang-rt-14-dev  # libFuzzer targets (scripts/fuzz.sh; ASan/UBSan runtimes)
  llvm-14                  # llvm-symbolizer: readable sanitizer stack traces
  libpetsc-real-dev        # PETSc 3.18 (pulls OpenMPI): fem.solver = petsc-gamg / petsc-hypre, mpirun solves
  openmpi-bin              # mpirun (the 2-rank solve_field test)
  python3                  # tests/layering/check_includes.py (the include-layering test)
  python3-dev python3-pybind11 pybind11-dev  # the Python module (python/)
  python3-numpy python3-pytest               # its arrays and its tests (ctest python_module_pytest)
  python3-pip python3-setuptools python3-wheel python3-venv  # pip install . (pyproject.toml, no network)
  python3-mypy                               # the package's type stubs checked (ctest python_stubs_mypy)
  python3-matplotlib python3-nbclient python3-nbformat python3-ipykernel  # examples/*.ipynb run by ctest
  libcpp-httplib-dev libjs-chart.js          # serve: its HTTP server and the page's charts
  chromium chromium-driver python3-selenium  # serve's page tested in a real headless browser (ctest serve_browser)
  libboost-dev             # Boost.Math quadrature: the independent reference of tests/fields/test_field_at.cpp
)
[ "$with_getdp" = 1 ] && PKGS+=(getdp gmsh)   # GetDP 3.2, gmsh 4.8 (scripts/bench_getdp.sh)
# ParaView (pvbatch) for the ParaView state tests is installed at the end by
# scripts/install_paraview_python.sh: NOT python3-paraview from apt, which on
# Debian 12 conflicts with python3-vtk9 and so would remove libvtk9-dev. A machine
# that already has python3-paraview gets one line saying so and what to do, and a
# non-zero exit (refuse_known_conflicts in apt_packages.sh), before apt runs.
. "$(dirname "$0")/apt_packages.sh"
install_missing_packages install_deps "${PKGS[@]}"
if [ "${MAGENC_WITH_PARAVIEW:-1}" = 1 ]; then
  "$(dirname "$0")/install_paraview_python.sh"   # paraview, xvfb, xauth + private python3-paraview
fi
