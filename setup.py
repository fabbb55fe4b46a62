"""Builds the extension module chromatag._chromatag with the project's CMake
build (pyproject.toml holds the package's metadata).

The libraries, their native code generation (CHROMATAG_NATIVE) and every
dependency are the ones `make build` uses; tests, benchmarks and the CLI are
left out. CMAKE_ARGS adds options (for example -DCHROMATAG_NATIVE=OFF for a
module that must run on other machines), CMAKE_BUILD_PARALLEL_LEVEL sets the
number of compile jobs.

CHROMATAG_BUILD_DIR names a build tree of this source (`make build`) whose
module is taken instead of compiling it again: setup.py still configures its
own tree with its own arguments (so the dependencies and options a user's
install meets are checked), then brings that build's chromatag_python up to
date and packages it. The pip test (tests/pip_install_test.sh) uses it.
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = Path(__file__).resolve().parent


def cmake_version():
    """The version CMakeLists.txt gives the project, the package's too."""
    text = (SOURCE_DIR / "CMakeLists.txt").read_text()
    match = re.search(r"project\(ChromaTag VERSION ([0-9.]+)", text)
    if not match:
        sys.exit("setup.py: no 'project(ChromaTag VERSION ...)' in CMakeLists.txt")
    return match.group(1)


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = Path(self.build_temp).resolve() / "cmake"
        configure = [
            "cmake", "-S", str(SOURCE_DIR), "-B", str(build_dir),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DCHROMATAG_BUILD_TESTS=OFF",
            "-DCHROMATAG_BUILD_BENCH=OFF",
            "-DCHROMATAG_BUILD_PYTHON=ON",
            "-DCHROMATAG_WERROR=OFF",
            f"-DPython3_EXECUTABLE={sys.executable}",
        ]
        if shutil.which("ninja"):
            configure += ["-G", "Ninja"]
        configure += shlex.split(os.environ.get("CMAKE_ARGS", ""))
        # A cache from a configure with other arguments (another generator,
        # an option since dropped from CMAKE_ARGS) would be reused silently,
        # or refused: start that build afresh.
        stamp = build_dir / "chromatag-configure.txt"
        if build_dir.exists() and (not stamp.exists() or stamp.read_text() != "\n".join(configure)):
            shutil.rmtree(build_dir)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        reuse = os.environ.get("CHROMATAG_BUILD_DIR")
        if reuse and not (Path(reuse) / "CMakeCache.txt").exists():
            sys.exit(f"CHROMATAG_BUILD_DIR={reuse} is not a CMake build tree (no CMakeCache.txt)")
        module_dir = Path(reuse).resolve() if reuse else build_dir
        try:
            subprocess.run(configure, check=True)
            stamp.write_text("\n".join(configure))
            subprocess.run(["cmake", "--build", str(module_dir), "--target", "chromatag_python",
                            "--parallel", jobs], check=True)
        except FileNotFoundError:
            sys.exit("building chromatag needs CMake and a C++ compiler: run scripts/install-deps.sh")
        except subprocess.CalledProcessError as e:
            sys.exit(f"building chromatag failed ({' '.join(e.cmd[:2])} exited {e.returncode}); "
                     "scripts/install-deps.sh installs what the build needs")
        built = list((module_dir / "python" / "chromatag").glob("_chromatag*.so"))
        if len(built) != 1:
            sys.exit(f"building chromatag: expected one _chromatag module in {module_dir}, found {built}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


# Under the CMake build folder, not beside it: setuptools would take build/.
setup(version=cmake_version(), ext_modules=[CMakeExtension("chromatag._chromatag")],
      cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build/pip"}})
