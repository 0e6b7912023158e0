#!/usr/bin/env bash
# The regression tests of over a minute each on the 2-core VM (CTest label `validation`), which CI
# leaves out (scripts/ci/test.sh); run them before a change to the method or the cases they cover:
#   bash scripts/ci/validation_tests.sh        (after scripts/ci/build.sh)
set -euo pipefail
cd "$(dirname "$0")/../../build"
OMP_NUM_THREADS=1 ctest --output-on-failure -j "$(nproc)" --timeout 1800 -L validation  # one thread per test (scripts/ci/test.sh)
