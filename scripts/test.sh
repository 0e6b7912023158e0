#!/usr/bin/env bash
# Set-up, build with warnings as errors, and every test (CTest labels unit, regression, device; the
# quick tier is `ctest -L quick`). Device tests skip without a GPU; ISPH_REQUIRE_GPU_TESTS=1 makes that
# skip a failure.
set -euo pipefail
cd "$(dirname "$0")/.."
ISPH_WERROR=ON bash scripts/build.sh
bash scripts/check_format.sh  # every C++ and CUDA file follows .clang-format
cd build
ctest --output-on-failure -j "$(nproc)" --timeout 900
cd ..
# A machine without nvcc builds without the CUDA backend (the README's fresh Debian 12). Where nvcc is
# present, the build above has it, so the library and the unit and device tests are built once more
# without it (build-no-cuda/) and run there: neither configuration can rot unseen.
if command -v nvcc > /dev/null || [ -x /usr/local/cuda/bin/nvcc ]; then
  cmake -S . -B build-no-cuda -DCMAKE_BUILD_TYPE=Release -DISPH_CUDA=OFF -DISPH_WERROR=ON
  cmake --build build-no-cuda -j "$(nproc)" --target isph_unit_tests isph_device_tests
  build-no-cuda/isph_unit_tests --gtest_brief=1
  build-no-cuda/isph_device_tests --gtest_brief=1
fi
# The unit tests and a handful of short runs under AddressSanitizer + UndefinedBehaviorSanitizer.
bash scripts/sanitize.sh
