#!/usr/bin/env bash
# Sets up (Debian packages + builds) and runs the whole test suite with CTest: the serial
# build, the decomposition tests (label mpi) of the MPI build under mpirun -np 2 and 4, and the
# unit and CLI tests once more in a checked build under ASan + UBSan (-DCMAKE_BUILD_TYPE=Sanitize:
# the sanitizers, libstdc++ assertions and the CMCSURF_DCHECKs of the ghost rule;
# docs/architecture.md, docs/reliability.md). The Checked build type (the same checks without
# the sanitizers, -O2) is still there for debugging; CI runs its checks in the sanitizer build.
# CMCSURF_BUILD_DIR, CMCSURF_MPI_BUILD_DIR and CMCSURF_ASAN_BUILD_DIR override ./build,
# ./build-mpi and ./build-asan; `none` skips all but the first.
set -euo pipefail
cd "$(dirname "$0")/.."
CMCSURF_EXTRA_PACKAGES="python3-vtk9 chromium ${CMCSURF_EXTRA_PACKAGES:-}" scripts/setup.sh "$@"
build="${CMCSURF_BUILD_DIR:-build}"
ctest --test-dir "$build" --output-on-failure -j 2 --timeout 600
mpi_build="${CMCSURF_MPI_BUILD_DIR:-build-mpi}"
if [ "$mpi_build" != none ]; then
  ctest --test-dir "$mpi_build" --output-on-failure -L mpi --timeout 600
fi
# The unit and CLI tests once more under AddressSanitizer + UndefinedBehaviorSanitizer
# (-DCMAKE_BUILD_TYPE=Sanitize; docs/reliability.md, "Sanitizers and fuzzing"): a memory error,
# a leak or undefined behaviour aborts its test (abort_on_error: SIGABRT, never mistaken for
# the exit 1 or 2 a CLI test expects). CMCSURF_ASAN_BUILD_DIR overrides ./build-asan; `none`
# skips it. Left to the serial build, to keep this pass near seven minutes on two cores (build
# five, tests two and a half): the three tests the checked pass leaves out; four unit tests
# that solve the same problem twice to compare two solver settings (the coarse-to-fine, the
# adaptive-dt and the combined fast run against the direct one, and a sweep's symmetry: 55 s
# of CPU here, their code runs here in the shorter Pipeline.* and Sweep.* tests);
# cli.checkpoint_resume_stages and cli.checkpoint_resume_fast (96^3 and 64^3 runs; the
# checkpoint writer, reader and resume run here in cli.checkpoint_resume at 16^3, Resume.*,
# ResumeCheck.*, cli.sweep_resume and the fuzz corpus); cli.sweep_resume_gallery (14 s here;
# the gallery's drawing runs in cli.sweep_outputs);
# and cli.report_page (the page's JavaScript in chromium; this build skips the npm bundle, and
# report.html's writer runs here in cli.run_outputs and cli.report_bad_input).
asan_build="${CMCSURF_ASAN_BUILD_DIR:-build-asan}"
if [ "$asan_build" != none ]; then
  cmake -S . -B "$asan_build" -DCMAKE_BUILD_TYPE=Sanitize -DCMCSURF_BUILD_BENCH=OFF \
        -DCMCSURF_WEB_VIEWER=OFF >/dev/null
  cmake --build "$asan_build" -j "$(nproc)" --target cmcsurf cmcsurf_tests
  asan_slow='^(parallel\.kernels_vs_reference|Sweep\.RelaxedSurfaceIsCloserToCmcThanTheNodalOne'
  asan_slow+='|Sweep\.ContinuationMemberReportsItsVolumeCorrections'
  asan_slow+='|Pipeline\.CoarseToFineMatchesDirectRun|Pipeline\.AdaptiveTimeStepsKeepTheResult'
  asan_slow+='|Pipeline\.FastCombinationMatchesPaperFaithfulRun'
  asan_slow+='|Sweep\.BalancedSurfaceIsSymmetricInVolumeFraction'
  asan_slow+='|cli\.checkpoint_resume_stages|cli\.checkpoint_resume_fast|cli\.sweep_resume_gallery'
  asan_slow+='|cli\.report_page'
  # Minutes each under the sanitizers on 2 cores (the release pass above runs them all):
  asan_slow+='|cli\.sweep_resume|cli\.scaffold_modes|cli\.scaffold_outputs|cli\.verify_quick'
  asan_slow+='|Part\.DecimationKeepsTheSolid'
  # Whole solves of the properties and a 32^3 scaffold member per case (release pass only; their
  # kernels run here in the Homogenize.*, CellProperties.* and Part.* unit tests):
  asan_slow+='|cli\.properties|cli\.scaffold_topology)$'
  ASAN_OPTIONS=abort_on_error=1 UBSAN_OPTIONS=abort_on_error=1:print_stacktrace=1 \
  LSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0" \
    ctest --test-dir "$asan_build" --output-on-failure -j 2 --timeout 600 -L 'unit|cli' \
          -E "$asan_slow"
fi
