#!/usr/bin/env bash
# Installs the Debian 12 packages cmcsurf needs and builds it in ./build (Release), and the
# MPI build (-DCMCSURF_MPI=ON, OpenMPI) in ./build-mpi.
# Usage: scripts/setup.sh [--no-install]    (CMCSURF_BUILD_DIR overrides ./build,
#        CMCSURF_MPI_BUILD_DIR ./build-mpi; CMCSURF_MPI_BUILD_DIR=none skips the MPI build;
#        CMCSURF_WERROR=ON makes compiler warnings errors, as scripts/test.sh does;
#        CMCSURF_CCACHE=ON installs ccache and compiles both builds through it, as
#        scripts/test.sh does, with its CCACHE_DIR)
set -euo pipefail
cd "$(dirname "$0")/.."
packages=(cmake g++ make libcli11-dev nlohmann-json3-dev libfmt-dev libmuparser-dev
          zlib1g-dev libgtest-dev libbenchmark-dev python3 python3-matplotlib python3-numpy
          admesh libopenmpi-dev openmpi-bin
          # Scaffolds (docs/scaffolds.md): 3MF files, mesh decimation, a shape's distance.
          lib3mf-dev libopenmesh-dev libopenvdb-dev
          # FFTs: effective properties (src/properties/) and structure factors (docs/science.md).
          libfftw3-dev pkg-config
          # The Python module (python/, docs/python.md) and its tests and examples.
          pybind11-dev python3-pybind11 python3-dev python3-pytest python3-tqdm
          python3-setuptools python3-wheel python3-pip python3-venv
          # Pictures and report.html (docs/report.md): stb (PNG, TrueType), the font, and npm
          # to bundle three.js at build time (a nodejs that brings its own npm is kept).
          libstb-dev fonts-dejavu-core
          # Periodic tetrahedral meshes (volume-mesh, docs/meshing.md): CGAL's periodic mesher,
          # Eigen for the tests' P1 solver, meshio and gmsh to read the files back in the tests.
          libcgal-dev libgmp-dev libmpfr-dev libeigen3-dev python3-meshio python3-h5py gmsh
          # XDMF's heavy data in HDF5 (the .h5 file FEniCS reads).
          libhdf5-dev)
command -v npm >/dev/null || packages+=(nodejs npm)
# Test-only tools (scripts/test.sh adds python3-vtk9, VTK's own reader of field.vti, and
# chromium, the headless browser that opens report.html).
read -r -a extra <<<"${CMCSURF_EXTRA_PACKAGES:-}"
packages+=("${extra[@]}")
# Opt-in (scripts/test.sh, CI): ccache, through which the MPI build takes the Release build's
# object files (all but parallel/'s have the same flags), instead of compiling them again.
use_ccache="${CMCSURF_CCACHE:-OFF}"
[ "$use_ccache" = OFF ] || packages+=(ccache)
# Opt-in: CMCSURF_FUZZ_BUILD_DIR=build-fuzz adds clang, libFuzzer and clang's OpenMP and builds
# the libFuzzer targets of fuzz/ there (docs/reliability.md, "Sanitizers and fuzzing").
fuzz_build="${CMCSURF_FUZZ_BUILD_DIR:-none}"
[ "$fuzz_build" = none ] || packages+=(clang libfuzzer-14-dev libomp-14-dev)
if [ "${1:-}" != "--no-install" ]; then
  missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
      missing+=("$p")
  done
  if [ "${#missing[@]}" -gt 0 ]; then
    echo "setup: installing ${missing[*]}"
    as_root=()
    [ "$(id -u)" -eq 0 ] || as_root=(sudo)
    export DEBIAN_FRONTEND=noninteractive
    "${as_root[@]}" apt-get update -qq
    "${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
fi
# CMCSURF_WERROR=ON (scripts/test.sh, CI) makes warnings errors; off for a user's build.
werror="${CMCSURF_WERROR:-OFF}"
launcher=()
if [ "$use_ccache" != OFF ]; then
  command -v ccache >/dev/null ||
    { echo "setup: CMCSURF_CCACHE=$use_ccache needs ccache (apt-get install ccache)" >&2; exit 2; }
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
build="${CMCSURF_BUILD_DIR:-build}"
start=$SECONDS
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMCSURF_WERROR="$werror" "${launcher[@]}" \
  >/dev/null
cmake --build "$build" -j "$(nproc)"
echo "setup: built $build/cmcsurf ($((SECONDS - start)) s)"
mpi_build="${CMCSURF_MPI_BUILD_DIR:-build-mpi}"
if [ "$mpi_build" != none ]; then
  # CMCSURF_CHECK_LAYERS=ON (scripts/test.sh, CI): its layers as shared libraries linked with
  # -Wl,--no-undefined, so a call up the layers of src/layers.txt fails to link.
  start=$SECONDS
  cmake -S . -B "$mpi_build" -DCMAKE_BUILD_TYPE=Release -DCMCSURF_MPI=ON \
        -DCMCSURF_BUILD_BENCH=OFF -DCMCSURF_WERROR="$werror" \
        -DCMCSURF_CHECK_LAYERS="${CMCSURF_CHECK_LAYERS:-OFF}" "${launcher[@]}" >/dev/null
  cmake --build "$mpi_build" -j "$(nproc)" --target cmcsurf cmcsurf_mpi_tests
  echo "setup: built $mpi_build/cmcsurf ($((SECONDS - start)) s; MPI: mpirun -np P" \
       "$mpi_build/cmcsurf run ...)"
fi
if [ "$fuzz_build" != none ]; then
  cmake -S . -B "$fuzz_build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMCSURF_FUZZ=ON -DCMCSURF_BUILD_TESTS=OFF -DCMCSURF_BUILD_BENCH=OFF \
        -DCMCSURF_WEB_VIEWER=OFF >/dev/null
  cmake --build "$fuzz_build" -j "$(nproc)" --target cmcsurf_fuzz
  echo "setup: built the fuzz targets in $fuzz_build/fuzz (docs/reliability.md)"
fi
