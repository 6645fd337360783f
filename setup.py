"""Builds the Python package magenc with the project's CMake (pyproject.toml; docs/python.md).

The compiled module magenc._magenc is the CMake target magenc_python. The CMake tree is
$MAGENC_BUILD_DIR when set (an existing tree, e.g. build/ of scripts/build.sh: only the target is
brought up to date), else a Release tree in setuptools' build_temp. CMAKE_BUILD_PARALLEL_LEVEL sets
the parallel jobs (default: all cores).
"""
import glob
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext: Extension) -> None:
        tree = os.environ.get("MAGENC_BUILD_DIR")
        if tree:
            tree_path = pathlib.Path(tree).resolve()
            if not (tree_path / "CMakeCache.txt").exists():
                sys.exit(f"MAGENC_BUILD_DIR={tree} is not a configured CMake tree: allowed a tree with CMakeCache.txt")
        else:
            tree_path = pathlib.Path(self.build_temp).resolve() / "cmake"
            if not (tree_path / "CMakeCache.txt").exists():
                cmd = ["cmake", "-S", str(ROOT), "-B", str(tree_path), "-DCMAKE_BUILD_TYPE=Release",
                       f"-DPython3_EXECUTABLE={sys.executable}"]
                if shutil.which("ccache"):
                    cmd.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
                subprocess.run(cmd, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(tree_path), "--target", "magenc_python", "-j", jobs], check=True)
        built = glob.glob(str(tree_path / "python" / "magenc" / "_magenc*.so"))
        if len(built) != 1:
            sys.exit(f"expected one python/magenc/_magenc*.so in {tree_path}, found {built}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


setup(
    packages=["magenc"],
    package_dir={"": "python"},
    package_data={"magenc": ["py.typed", "*.pyi"]},
    ext_modules=[Extension("magenc._magenc", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
