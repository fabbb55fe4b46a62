"""Builds the extension module chromatag._chromatag with the project's CMake
build (pyproject.toml holds the package's metadata).

The libraries, their native code generation (CHROMATAG_NATIVE) and every
dependency are the ones `make build` uses; tests, benchmarks and the CLI are
left out. CMAKE_ARGS adds options (for example -DCHROMATAG_NATIVE=OFF for a
module that must run on other machines), CMAKE_BUILD_PARALLEL_LEVEL sets the
number of compile jobs.
"""
import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = Path(__file__).resolve().parent


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
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        try:
            subprocess.run(configure, check=True)
            subprocess.run(["cmake", "--build", str(build_dir), "--target", "chromatag_python",
                            "--parallel", jobs], check=True)
        except FileNotFoundError:
            sys.exit("building chromatag needs CMake and a C++ compiler: run scripts/install-deps.sh")
        except subprocess.CalledProcessError as e:
            sys.exit(f"building chromatag failed ({' '.join(e.cmd[:2])} exited {e.returncode}); "
                     "scripts/install-deps.sh installs what the build needs")
        built = list((build_dir / "python" / "chromatag").glob("_chromatag*.so"))
        if len(built) != 1:
            sys.exit(f"building chromatag: expected one _chromatag module in {build_dir}, found {built}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


# Under the CMake build folder, not beside it: setuptools would take build/.
setup(ext_modules=[CMakeExtension("chromatag._chromatag")], cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build/pip"}})
