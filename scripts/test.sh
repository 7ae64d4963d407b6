#!/usr/bin/env bash
# Sets up (Debian packages + builds) and runs the whole test suite with CTest: the serial
# build, then the decomposition tests (label mpi) of the MPI build under mpirun -np 2 and 4.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh "$@"
build="${CMCSURF_BUILD_DIR:-build}"
ctest --test-dir "$build" --output-on-failure -j 2 --timeout 600
mpi_build="${CMCSURF_MPI_BUILD_DIR:-build-mpi}"
if [ "$mpi_build" != none ]; then
  ctest --test-dir "$mpi_build" --output-on-failure -L mpi --timeout 600
fi
