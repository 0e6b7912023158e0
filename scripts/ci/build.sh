#!/usr/bin/env bash
# Installs what is missing (scripts/ci/setup.sh) and builds in build/ (Release): every target, or the
# targets named (scripts/ci/test.sh builds the solver and its tests, not the benchmark programs). CUDA,
# HDF5 and hypre are used when found; the configure step says which are missing. ISPH_WERROR=ON
# (scripts/ci/test.sh, CI) makes compiler warnings errors.
#   bash scripts/ci/build.sh [TARGET ...]
set -euo pipefail
cd "$(dirname "$0")/../.."
bash scripts/ci/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release ${ISPH_WERROR:+-DISPH_WERROR="$ISPH_WERROR"}
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j "$(nproc)" "${targets[@]}"
