#!/usr/bin/env bash
# Sets up (Debian packages + builds, warnings as errors) and runs the whole test suite with
# CTest: the serial build (with the style gate, label lint), the decomposition tests (label mpi)
# of the MPI build under mpirun -np 2 and 4, and the unit and CLI tests once more in a checked
# build under ASan + UBSan (-DCMAKE_BUILD_TYPE=Sanitize:
# the sanitizers, libstdc++ assertions and the CMCSURF_DCHECKs of the ghost rule;
# docs/architecture.md, docs/reliability.md). The Checked build type (the same checks without
# the sanitizers, -O2) is still there for debugging; CI runs its checks in the sanitizer build.
# CMCSURF_BUILD_DIR, CMCSURF_MPI_BUILD_DIR and CMCSURF_ASAN_BUILD_DIR override ./build,
# ./build-mpi and ./build-asan; `none` skips all but the first.
set -euo pipefail
cd "$(dirname "$0")/.."
# Warnings are errors in CI's builds (CMCSURF_WERROR; a user's scripts/setup.sh leaves it off),
# and the MPI build links each layer as a shared library with -Wl,--no-undefined
# (CMCSURF_CHECK_LAYERS), where a call up the layers fails to link.
# Every build compiles through ccache (CMCSURF_CCACHE, which installs it), so that the MPI
# build takes the Release build's objects. Its cache is build-ccache/ in this clone: CI's fresh
# clone starts empty and keeps nothing, a rerun here recompiles only what changed.
export CCACHE_DIR="$PWD/build-ccache" CCACHE_BASEDIR="$PWD" CCACHE_DEPEND=1
phases=()
phase() {  # <name> <start>: the wall time of each phase, printed again at the end
  phases+=("$1 $((SECONDS - $2)) s")
  echo "test.sh: ${phases[-1]}"
}
start=$SECONDS
CMCSURF_WERROR=ON CMCSURF_CHECK_LAYERS=ON CMCSURF_CCACHE=ON \
  CMCSURF_EXTRA_PACKAGES="python3-vtk9 chromium ninja-build ${CMCSURF_EXTRA_PACKAGES:-}" \
  scripts/setup.sh "$@"
phase "setup (packages, Release and MPI builds)" $start
build="${CMCSURF_BUILD_DIR:-build}"
start=$SECONDS
ctest --test-dir "$build" --output-on-failure -j 2 --timeout 600
phase "Release tests" $start
mpi_build="${CMCSURF_MPI_BUILD_DIR:-build-mpi}"
if [ "$mpi_build" != none ]; then
  start=$SECONDS
  ctest --test-dir "$mpi_build" --output-on-failure -L mpi --timeout 600
  phase "MPI tests" $start
fi
# The unit and CLI tests once more under AddressSanitizer + UndefinedBehaviorSanitizer
# (-DCMAKE_BUILD_TYPE=Sanitize; docs/reliability.md, "Sanitizers and fuzzing"): a memory error,
# a leak or undefined behaviour aborts its test (abort_on_error: SIGABRT, never mistaken for
# the exit 1 or 2 a CLI test expects). CMCSURF_ASAN_BUILD_DIR overrides ./build-asan; `none`
# skips it. Tests are chosen by label (CMakeLists.txt, where they are registered): left to the
# release pass above are those labelled slow (15 s to minutes each under the sanitizers on two
# cores; their code runs here in shorter tests), browser (chromium and the npm bundle, which
# this build skips) and threads (the two-thread pass; its kernels run here with one thread).
# docs/reliability.md, "Sanitizers and fuzzing", has the times of each phase.
asan_build="${CMCSURF_ASAN_BUILD_DIR:-build-asan}"
if [ "$asan_build" != none ]; then
  start=$SECONDS
  # Ninja where it is installed (ninja-build, above): make builds the layers one after another,
  # Ninja compiles every layer's batches as soon as a core is free (this build from nothing on
  # two idle cores: 762 s with make, 640 s with Ninja; docs/reliability.md, "CI time"). A
  # folder configured before keeps its generator.
  generator=()
  if [ ! -e "$asan_build/CMakeCache.txt" ] && command -v ninja >/dev/null; then
    generator=(-G Ninja)
  fi
  cmake -S . -B "$asan_build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Sanitize \
        -DCMCSURF_BUILD_BENCH=OFF -DCMCSURF_WEB_VIEWER=OFF -DCMCSURF_WERROR=ON \
        -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null
  cmake --build "$asan_build" -j "$(nproc)" --target cmcsurf cmcsurf_tests
  phase "sanitizer build" $start
  start=$SECONDS
  ASAN_OPTIONS=abort_on_error=1 UBSAN_OPTIONS=abort_on_error=1:print_stacktrace=1 \
  LSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0" \
    ctest --test-dir "$asan_build" --output-on-failure -j 2 --timeout 600 -L 'unit|cli' \
          -LE 'slow|browser|threads'
  phase "sanitizer tests" $start
fi
printf 'test.sh: %s\n' "${phases[@]}" "total $SECONDS s"
