"""pip install --no-build-isolation --no-index ./python: builds and packages the module.

From a clean checkout it builds the compiled part itself: setuptools drives CMake (as pybind11's
cmake_example does) to build the target cmcsurf_python alone, offline, with Debian's packages
(scripts/setup.sh's list; pybind11-dev, python3-dev, python3-setuptools, python3-wheel), for the
Python that runs pip, in python/build (kept, so a second install rebuilds only what changed).
The module is tuned for any x86-64, not the build machine: CMCSURF_NATIVE=1 asks for
-march=native. CMAKE_ARGS adds options to the configure step (e.g. -DCMCSURF_MPI=ON, or
-DCMCSURF_WEB_VIEWER=ON where npm may download the page's 3D view); CMAKE_BUILD_PARALLEL_LEVEL
sets the jobs (default: all cores).

With CMCSURF_BUILD_DIR set it compiles nothing and packages the module an earlier CMake build
made (scripts/setup.sh, or cmake --build BUILD --target cmcsurf_python): it copies
<build>/python/cmcsurf/_cmcsurf*.so beside the Python files. The folder is absolute or relative
to the repository root; setuptools' own build files go to <build>/python/setup, not into python/.
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Distribution, Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, ".."))
# A prebuilt module's build folder, relative to the repository root, where the README's commands
# run; None: build the module here.
PREBUILT = os.environ.get("CMCSURF_BUILD_DIR") or None
BUILD = os.path.abspath(os.path.join(ROOT, PREBUILT)) if PREBUILT else None
SETUP_BUILD = os.path.join(BUILD, "python", "setup") if PREBUILT else None


def compiled_module():
    """The module built for this interpreter: _cmcsurf<EXT_SUFFIX>, e.g.
    _cmcsurf.cpython-311-x86_64-linux-gnu.so; one for another Python's ABI is refused."""
    folder = os.path.join(BUILD, "python", "cmcsurf")
    suffix = sysconfig.get_config_var("EXT_SUFFIX")
    wanted = os.path.join(folder, "_cmcsurf" + suffix)
    if os.path.exists(wanted):
        return wanted
    found = sorted(os.path.basename(f) for f in glob.glob(os.path.join(folder, "_cmcsurf*.so")))
    if found:
        raise SystemExit(
            f"cmcsurf: {folder} has {', '.join(found)}, built for another Python; this one "
            f"({sysconfig.get_config_var('VERSION')}) needs _cmcsurf{suffix}: configure the build "
            "with -DPython_EXECUTABLE=<this python> or install with the Python it was built for")
    raise SystemExit(
        f"cmcsurf: no compiled module in {folder}; build it first (scripts/setup.sh, or "
        "cmake --build build --target cmcsurf_python), or unset CMCSURF_BUILD_DIR to build it "
        "in the install")


def project_version():
    with open(os.path.join(HERE, "..", "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(cmcsurf VERSION ([0-9.]+)", f.read()).group(1)


class BuildWithModule(build_py):
    def run(self):
        super().run()
        module = compiled_module()
        target = os.path.join(self.build_lib, "cmcsurf")
        os.makedirs(target, exist_ok=True)
        # Always copied (setuptools' copy_file keeps a newer file already there).
        shutil.copyfile(module, os.path.join(target, os.path.basename(module)))


class CMakeExtension(Extension):
    """The module cmcsurf._cmcsurf, built by CMake from the repository (no sources of its own)."""

    def __init__(self, name):
        super().__init__(name, sources=[])


def flag(name):
    return os.environ.get(name, "").strip().lower() not in ("", "0", "off", "no", "false")


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        target = os.path.abspath(self.get_ext_fullpath(ext.name))
        work = os.path.abspath(os.path.join(self.build_temp, "cmake"))
        os.makedirs(work, exist_ok=True)
        configure = [
            "cmake", "-S", ROOT, "-B", work, "-DCMAKE_BUILD_TYPE=Release",
            f"-DPython_EXECUTABLE={sys.executable}", "-DCMCSURF_PYTHON=ON",
            "-DCMCSURF_BUILD_TESTS=OFF", "-DCMCSURF_BUILD_BENCH=OFF", "-DCMCSURF_WEB_VIEWER=OFF",
            f"-DCMCSURF_NATIVE={'ON' if flag('CMCSURF_NATIVE') else 'OFF'}",
        ] + os.environ.get("CMAKE_ARGS", "").split()
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        build = ["cmake", "--build", work, "--target", "cmcsurf_python", "-j", jobs]
        try:
            subprocess.run(configure, check=True)
            subprocess.run(build, check=True)
        except FileNotFoundError:
            raise SystemExit("cmcsurf: building the module needs cmake (Debian cmake, and the "
                             "packages of scripts/setup.sh)")
        except subprocess.CalledProcessError as e:
            raise SystemExit(f"cmcsurf: {' '.join(e.cmd[:3])} ... failed (exit {e.returncode})")
        built = os.path.join(work, "python", "cmcsurf", os.path.basename(target))
        if not os.path.exists(built):
            raise SystemExit(f"cmcsurf: CMake built no {built} (is pybind11-dev installed? the "
                             "configure step says why it skipped the module)")
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built, target)


class BinaryDistribution(Distribution):
    def has_ext_modules(self):  # a platform wheel: the package holds a compiled module
        return True


OPTIONS = {}
if PREBUILT:
    CMDCLASS = {"build_py": BuildWithModule}
    EXT_MODULES = []
    # setuptools' build files beside the module (when the build folder exists; else setuptools'
    # default, python/build, and compiled_module() says what is missing).
    if os.path.isdir(BUILD):
        os.makedirs(SETUP_BUILD, exist_ok=True)
        OPTIONS = {"build": {"build_base": SETUP_BUILD}, "egg_info": {"egg_base": SETUP_BUILD}}
else:
    CMDCLASS = {"build_ext": CMakeBuild}
    EXT_MODULES = [CMakeExtension("cmcsurf._cmcsurf")]
setup(
    name="cmcsurf",
    version=project_version(),
    description="Triply periodic constant-mean-curvature surfaces (Cahn-Hilliard + FAS multigrid)",
    packages=["cmcsurf"],
    package_data={"cmcsurf": ["*.pyi", "py.typed"]},
    python_requires=">=3.9",
    install_requires=["numpy"],
    ext_modules=EXT_MODULES,
    cmdclass=CMDCLASS,
    distclass=BinaryDistribution,
    zip_safe=False,
    options=OPTIONS,
)
