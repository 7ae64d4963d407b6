"""pip install --no-build-isolation --no-index ./python: packages the module that CMake built.

The compiled part is built with the rest of the project (scripts/setup.sh, or cmake --build):
this script only copies <build>/python/cmcsurf/_cmcsurf*.so beside the Python files, so the
install needs nothing beyond Debian's python3-setuptools and python3-wheel (no network).
CMCSURF_BUILD_DIR names the build folder, absolute or relative to the repository root (default:
build). setuptools' own build files go to <build>/python/setup, not into python/.
"""
import glob
import os
import re
import shutil
import sysconfig

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
# Relative to the repository root, where the README's commands run.
BUILD = os.path.join(HERE, "..", os.environ.get("CMCSURF_BUILD_DIR", "build"))
BUILD = os.path.abspath(BUILD)
SETUP_BUILD = os.path.join(BUILD, "python", "setup")


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
        "cmake --build build --target cmcsurf_python) or set CMCSURF_BUILD_DIR")


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


class BinaryDistribution(Distribution):
    def has_ext_modules(self):  # a platform wheel: the package holds a compiled module
        return True


# setuptools' build files beside the module (when the build folder exists; else setuptools'
# default, python/build, and compiled_module() says what is missing).
OPTIONS = {}
if os.path.isdir(BUILD):
    os.makedirs(SETUP_BUILD, exist_ok=True)
    OPTIONS = {"build": {"build_base": SETUP_BUILD}, "egg_info": {"egg_base": SETUP_BUILD}}
setup(
    name="cmcsurf",
    version=project_version(),
    description="Triply periodic constant-mean-curvature surfaces (Cahn-Hilliard + FAS multigrid)",
    packages=["cmcsurf"],
    package_data={"cmcsurf": ["*.pyi", "py.typed"]},
    python_requires=">=3.9",
    install_requires=["numpy"],
    cmdclass={"build_py": BuildWithModule},
    distclass=BinaryDistribution,
    zip_safe=False,
    options=OPTIONS,
)
