#!/usr/bin/env bash
# Fuzzes the case loader (TOML text, --set overrides, a motion CSV; tests/fuzz/case_input.hpp) with
# libFuzzer for SECONDS (default 1800), built with clang, AddressSanitizer and UndefinedBehaviorSanitizer
# in build-fuzz/. The fuzzer works in a scratch corpus (build-fuzz/corpus, seeded from tests/fuzz/corpus);
# a merge (-merge=1) then adds to tests/fuzz/corpus only the inputs that reach features it lacks, so
# the tracked corpus stays minimal. Crashing inputs go to tests/fuzz/crashes/ (FuzzCorpus.* replays
# both in every test run). Usage: scripts/ci/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds="${1:-1800}"
CXX=clang++ CC=clang cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DISPH_CUDA=OFF -DISPH_FUZZ=ON \
  -DISPH_BUILD_TESTS=OFF
cmake --build build-fuzz -j "$(nproc)" --target isph_fuzz_case
mkdir -p tests/fuzz/crashes
# Leak checks stay with scripts/ci/sanitize.sh, which replays the corpus: here they would cost a full stack
# unwind on every allocation (needed to recognise Open MPI's leaks) and make the fuzzer 100 times slower.
options=(-timeout=10 -rss_limit_mb=4096 -max_len=65536 -detect_leaks=0)
mkdir -p build-fuzz/corpus
build-fuzz/isph_fuzz_case build-fuzz/corpus tests/fuzz/corpus -max_total_time="$seconds" "${options[@]}" \
  -artifact_prefix=tests/fuzz/crashes/ -print_final_stats=1
build-fuzz/isph_fuzz_case -merge=1 "${options[@]}" tests/fuzz/corpus build-fuzz/corpus
