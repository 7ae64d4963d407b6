"""pip install --no-build-isolation ./python: packages the module that the CMake build made.

The compiled part is built with the rest of the project (scripts/setup.sh, or cmake --build):
this script only copies <build>/python/cmcsurf/_cmcsurf*.so beside the Python files, so the
install needs nothing beyond Debian's python3-setuptools and python3-wheel (no network).
CMCSURF_BUILD_DIR names the build folder, relative to the repository root (default: build).
"""
import glob
import os
import re

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
# Relative to the repository root, where the README's commands run.
BUILD = os.path.join(HERE, "..", os.environ.get("CMCSURF_BUILD_DIR", "build"))
BUILD = os.path.abspath(BUILD)


def project_version():
    with open(os.path.join(HERE, "..", "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(cmcsurf VERSION ([0-9.]+)", f.read()).group(1)


class BuildWithModule(build_py):
    def run(self):
        super().run()
        found = glob.glob(os.path.join(BUILD, "python", "cmcsurf", "_cmcsurf*.so"))
        if not found:
            raise SystemExit(
                f"cmcsurf: no compiled module in {BUILD}/python/cmcsurf; build it first "
                "(scripts/setup.sh, or cmake --build build) or set CMCSURF_BUILD_DIR")
        self.copy_file(found[0], os.path.join(self.build_lib, "cmcsurf"))


class BinaryDistribution(Distribution):
    def has_ext_modules(self):  # a platform wheel: the package holds a compiled module
        return True


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
)
