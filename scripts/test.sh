#!/usr/bin/env bash
# The whole test suite: sets up and builds (scripts/setup.sh, idempotent), then runs CTest:
# opencv_test_forestmod (accuracy), opencv_sanity_forestmod (a short run of every perf test),
# forestmod_install_consumer (install + find_package(forestmod) from another project) and
# forestmod_scripts (the tests of scripts/verification_weights.py).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${FORESTMOD_BUILD_DIR:-$root/build}
"$root/scripts/setup.sh"
cd "$build"
ctest --output-on-failure --timeout 1500 "$@"
