#!/usr/bin/env bash
# Set-up, build with warnings as errors, and every test of CI: the CTest labels quick-regression,
# regression and device (all but `validation`, the tests of over a minute, which
# scripts/ci/validation_tests.sh runs), longest first; then the sanitizers (scripts/ci/sanitize.sh, a build
# without CUDA, which also covers a machine without nvcc), which run the unit tests: this build leaves
# them out (their placeholder tests end in _NOT_BUILT). Device tests skip without a GPU;
# ISPH_REQUIRE_GPU_TESTS=1 makes that skip a failure.
set -euo pipefail
cd "$(dirname "$0")/../.."
SECONDS=0
ISPH_WERROR=ON bash scripts/ci/build.sh isph isph_regression_tests isph_device_tests
echo "test: built in ${SECONDS} s"
bash scripts/ci/check_format.sh
# CTest starts the tests it knows to be long first (its cost data: each test's time on the 2-core VM),
# so that both cores stay busy to the end; a fresh clone has none, so the measured costs are copied in.
mkdir -p build/Testing/Temporary
cp tests/ctest_cost.txt build/Testing/Temporary/CTestCostData.txt
# One OpenMP thread per test: the tests run side by side on every core, and parallel regions on
# oversubscribed cores wait for time slices at every barrier.
(cd build && OMP_NUM_THREADS=1 ctest --output-on-failure -j "$(nproc)" --timeout 900 -LE 'validation|unit' \
  -E '_NOT_BUILT$')
echo "test: tests passed at ${SECONDS} s"
bash scripts/ci/sanitize.sh
echo "test: done in ${SECONDS} s"
