#!/usr/bin/env bash
# Sets up (Debian packages + build) and runs the whole test suite with CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh "$@"
build="${CMCSURF_BUILD_DIR:-build}"
ctest --test-dir "$build" --output-on-failure -j 2 --timeout 600
