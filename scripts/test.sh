#!/usr/bin/env bash
# Set-up, build, and every test (CTest labels unit, regression, device). Device tests skip without
# a GPU; ISPH_REQUIRE_GPU_TESTS=1 makes that skip a failure.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
cd build
ctest --output-on-failure -j "$(nproc)" --timeout 900
