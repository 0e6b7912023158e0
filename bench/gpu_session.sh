#!/bin/bash
# The GPU checks and benchmarks of issue 5 in one command, for a lent GPU machine (docs/PERFORMANCE.md).
#
#   bash bench/gpu_session.sh BUILD_DIR OUT_DIR [STEP...]
#
# BUILD_DIR holds a CUDA build (cmake -DISPH_CUDA=ON; HDF5 and hypre may be off). If its programs do
# not start on this machine (other system libraries), the script configures and builds one in
# build-device, taking Eigen, toml11, CLI11 and GoogleTest from the Debian packages in .deps/debs
# (apt-get download libeigen3-dev libtoml11-dev libcli11-dev libgtest-dev), since the GPU machine has
# no package registry.
# Steps (default: all): tests  sanitize  pairs  spmv  solvers  substeps  plate  shipped  fluid  large
#   tests   : the device tests with ISPH_REQUIRE_GPU_TESTS=1 (a skip is a failure), stopped after
#             TESTS_TIMEOUT seconds (default 1800)
#   sanitize: the device tests under compute-sanitizer memcheck (out-of-bounds and misaligned accesses)
#   pairs   : isph_pair_bench, 1e4 to 4e6 particles, host (all cores) and GPU
#   spmv    : isph_ppe_bench --spmv-only, cuSPARSE, the vector CSR kernel and the host SpMV against the
#             copy bandwidth
#   solvers : isph_ppe_bench, every backend on the manufactured PPE at 1e5 and 1e6 unknowns
#   substeps: isph_substep_bench, one RK4 structure substep with its interaction power, from 540 to 2e6
#             particles: host; device with launches one by one, with a CUDA graph (both waiting at
#             every substep), and queued (advance: one wait for all the substeps)
#   plate   : the oscillating plate (cases/oscillating_plate.toml) at T/dx = 10 (0.7 s) and 20 (0.2 s) on
#             the cpu (all cores) and with --device cuda; the tip histories are compared (to 1e-8)
#   shipped : the FSI cases as shipped (multi-resolution elastic gate, hydrostatic plate, Walhorn
#             obstacle), each to SHIPPED_END_TIME (default 0.1 s; a run stopped after SHIPPED_TIMEOUT s,
#             default 240), with --device cuda (cuda BiCGSTAB +
#             AMG) and on the cpu with all cores (native BiCGSTAB + the same AMG; hypre is not in this
#             build); summaries, probes and energies in OUT_DIR/shipped.tar.gz, a table in shipped.md
#   fluid   : bench/case_sweep.py, the dam break and the gate (SWEEP_CASES) from 1e4 to 1e6 (SWEEP_SIZES)
#             fluid particles, each run stopped after SWEEP_TIMEOUT seconds where that is set, with
#             --device cuda and the PPE on the device (cuda BiCGSTAB + the AMG of
#             poisson/aggregation_amg.hpp; Jacobi and the polynomial preconditioner do not converge at
#             1e5 and above), then on the cpu with all cores and the same solver on the host (native
#             BiCGSTAB + the same AMG), the 10x comparison of issue 5
#   large   : the same cuda sweep at 4e6 fluid particles
# Logs and tables go to OUT_DIR.
# A lent machine has 15 minutes of device time, its start included. With SESSION_SECONDS set, a step
# that would begin later than that many seconds after the script started is skipped (and says so), so
# that the script returns inside the run's timeout with what it has. Suggested first call (about
# 9 minutes), with a build without HDF5 and hypre made here beforehand,
#   cmake -S . -B .gpu-build -DISPH_CUDA=ON -DISPH_HDF5=OFF -DISPH_HYPRE=OFF -DCMAKE_BUILD_TYPE=Release
#   cmake --build .gpu-build -j2 --target isph isph_device_tests isph_pair_bench isph_ppe_bench isph_substep_bench
# and only its five programs carried (the device tool's carry: .gpu-build/isph, .gpu-build/isph_device_tests, ...):
#   SESSION_SECONDS=420 bash bench/gpu_session.sh .gpu-build "$OUT" tests spmv fluid large
set -u -o pipefail
build=${1:?build directory}
out=${2:?output directory}
shift 2
steps=${*:-tests sanitize pairs spmv solvers substeps plate shipped fluid large}
sweep_sizes=${SWEEP_SIZES:-1e4,1e5,1e6}
sweep_cases=${SWEEP_CASES:-dam_break,elastic_gate}
sweep_timeout=${SWEEP_TIMEOUT:-0}  # seconds per run of the sweeps (0: none)
mkdir -p "$out"
export LD_LIBRARY_PATH=/usr/local/cuda/lib64:/usr/local/cuda/lib:${LD_LIBRARY_PATH:-}
# The device tests run cases from this checkout with this build's isph, wherever both were built.
export ISPH_TEST_SOURCE_DIR="$PWD" ISPH_TEST_BINARY="$(cd "$build" && pwd)/isph"

nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.sm,clocks.mem --format=csv | tee "$out/gpu.txt"
nproc | sed 's/^/cores: /' | tee -a "$out/gpu.txt"

if ! "$build/isph_device_tests" --gtest_list_tests >/dev/null 2>&1; then
  echo "programs in $build do not start here; building in build-device"
  mkdir -p .deps/root && for f in .deps/debs/*.deb; do dpkg -x "$f" .deps/root; done
  cmake -S . -B build-device -DISPH_CUDA=ON -DISPH_HDF5=OFF -DISPH_HYPRE=OFF \
    -DCMAKE_PREFIX_PATH="$PWD/.deps/root/usr" >"$out/build.log" 2>&1 &&
    cmake --build build-device -j "$(nproc)" --target isph isph_device_tests isph_pair_bench isph_ppe_bench \
      >>"$out/build.log" 2>&1 || { tail -40 "$out/build.log"; exit 1; }
  build=build-device
  export ISPH_TEST_BINARY="$PWD/build-device/isph"
fi

status=0
session_start=$(date +%s)
for step in $steps; do
  start=$(date +%s)
  if [ -n "${SESSION_SECONDS:-}" ] && [ $((start - session_start)) -ge "$SESSION_SECONDS" ]; then
    echo "step $step: skipped ($((start - session_start)) s of SESSION_SECONDS=$SESSION_SECONDS used)"
    continue
  fi
  case $step in
    tests)
      ISPH_REQUIRE_GPU_TESTS=1 timeout "${TESTS_TIMEOUT:-1800}" "$build/isph_device_tests" 2>&1 | tee "$out/device_tests.log" | grep -E "^\[  (PASSED|FAILED|SKIPPED) |OK \]|FAILED|Failure" || status=1 ;;
    sanitize)
      ISPH_REQUIRE_GPU_TESTS=1 compute-sanitizer --tool memcheck --leak-check no "$build/isph_device_tests" \
        >"$out/sanitizer.log" 2>&1 || status=1
      tail -3 "$out/sanitizer.log" ;;
    pairs)
      "$build/isph_pair_bench" 1e4 1e5 1e6 4e6 2>&1 | tee "$out/pair_bench.md" || status=1 ;;
    spmv)
      "$build/isph_ppe_bench" --spmv-only 1e5 1e6 4e6 2>&1 | tee "$out/spmv_bench.md" || status=1 ;;
    solvers)
      "$build/isph_ppe_bench" --skip-over 40 1e5 1e6 2>&1 | tee "$out/solver_bench.md" || status=1 ;;
    substeps)
      "$build/isph_substep_bench" 2>&1 | tee "$out/substep_bench.md" || status=1 ;;
    plate)
      for spec in "10 0.002 0.7" "20 0.001 0.2"; do
        read -r res dx end <<<"$spec"
        for device in cpu cuda; do
          "$build/isph" run cases/oscillating_plate.toml --device $device --out "/tmp/plate_${res}_$device" \
            --set dx=$dx --set end_time=$end --set output.snapshot_interval=0 >/dev/null 2>&1 || status=1
          python3 -c "import json,sys; s=json.load(open(sys.argv[1])); p=s['phases']; print('<!-- plate T/dx=$res $device:', s.get('status'), 'steps', s.get('steps'), 'wall', s.get('wall_time_s'), 'phases', p, 'perf', s.get('performance'), '-->')" \
            "/tmp/plate_${res}_$device/summary.json" | tee -a "$out/plate.md"
        done
        python3 bench/compare_probes.py "/tmp/plate_${res}_cpu/probes.csv" "/tmp/plate_${res}_cuda/probes.csv" \
          | tee -a "$out/plate.md" || status=1
      done ;;
    shipped)
      end=${SHIPPED_END_TIME:-0.1}
      for name in elastic_gate hydrostatic_plate baffle_walhorn; do
        for device in cuda cpu; do
          backend=$([ $device = cuda ] && echo cuda || echo native)
          timeout "${SHIPPED_TIMEOUT:-240}" "$build/isph" run cases/$name.toml --device $device --threads "$(nproc)" --quiet \
            --out "/tmp/shipped/${name}_$device" --set end_time=$end --set output.snapshots=false \
            --set fluid.ppe.backend=$backend --set fluid.ppe.preconditioner=amg --set fluid.ppe.fallback=none \
            >"/tmp/shipped_${name}_$device.log" 2>&1 || { status=1; tail -3 "/tmp/shipped_${name}_$device.log"; }
          python3 -c "import json,sys; s=json.load(open(sys.argv[1])); p=s['phases']; print('| $name | $device |', s['status'], '|', s['steps'], '|', round(s['wall_time_s'], 2), '|', s['ppe'], '|', {k: round(v, 2) for k, v in p.items()}, '|')" \
            "/tmp/shipped/${name}_$device/summary.json" 2>/dev/null | tee -a "$out/shipped.md"
        done
      done
      tar czf "$out/shipped.tar.gz" -C /tmp shipped ;;
    fluid)
      ISPH="$build/isph" python3 bench/case_sweep.py --sizes "$sweep_sizes" --cases "$sweep_cases" --timeout "$sweep_timeout" --device cuda --threads "$(nproc)" \
        --backend cuda --preconditioner amg --out "$out/sweep_cuda" 2>&1 | tee "$out/fluid_sweep_cuda.md" || status=1
      ISPH="$build/isph" python3 bench/case_sweep.py --sizes "$sweep_sizes" --cases "$sweep_cases" --timeout "$sweep_timeout" --device cpu --threads "$(nproc)" \
        --backend native --preconditioner amg --out "$out/sweep_cpu" 2>&1 | tee "$out/fluid_sweep_cpu.md" || status=1 ;;
    large)
      ISPH="$build/isph" python3 bench/case_sweep.py --sizes 4e6 --device cuda --threads "$(nproc)" \
        --backend cuda --preconditioner amg --out "$out/sweep_cuda_4e6" 2>&1 | tee "$out/fluid_sweep_cuda_4e6.md" || status=1 ;;
    *) echo "unknown step $step"; status=1 ;;
  esac
  echo "step $step: $(( $(date +%s) - start )) s"
done
exit $status
