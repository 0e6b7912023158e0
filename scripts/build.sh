#!/usr/bin/env bash
# Installs what is missing (scripts/setup.sh) and builds in build/ (Release). CUDA, HDF5 and hypre
# are used when found; the configure step says which are missing. ISPH_WERROR=ON (scripts/test.sh, CI)
# makes compiler warnings errors.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release ${ISPH_WERROR:+-DISPH_WERROR="$ISPH_WERROR"}
cmake --build build -j "$(nproc)"
