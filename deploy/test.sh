#!/usr/bin/env bash
# README command (b): set up, build, and run every test.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
if [ "$(id -u)" -eq 0 ]; then bash deploy/setup.sh; else sudo bash deploy/setup.sh; fi
bash deploy/build.sh
ctest --test-dir "${DF_BUILD:-$root/build}" --output-on-failure -j "${DF_TEST_JOBS:-2}" --timeout 600

# Sanitizers (docs/hardening.md, "Sanitizers"): the unit tests (not the integration or hostile tests)
# built with clang, AddressSanitizer and UndefinedBehaviorSanitizer, then every fuzz target over
# its corpus and ${DF_FUZZ_SECONDS:-20} s of fuzzing. On by default; DF_SANITIZERS=0 skips it.
if [ "${DF_SANITIZERS:-1}" != 0 ]; then
  asan="${DF_BUILD_ASAN:-$root/build-asan}"
  if [ ! -f "$asan/CMakeCache.txt" ]; then
    CC=clang CXX=clang++ cmake -S "$root" -B "$asan" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -gline-tables-only" \
      "-DCMAKE_C_FLAGS_RELEASE=-O1 -gline-tables-only" \
      -DDF_SANITIZE=address,undefined -DDF_FUZZ=ON -DDF_BUILD_BENCHMARKS=OFF >/dev/null
  fi
  # Left out by default, to keep the step inside CI's time: five tests that each render or track
  # whole generated sequences and take 10-15 min under ASan on 2 cores (df_sim_sequence_test,
  # df_slam_checkpoint_test, df_slam_accuracy_test, df_dynamic_accuracy_test,
  # df_object_maps_test); they run unsanitized in the suite above, and the same code runs
  # sanitized on shorter inputs in df_sim_test, df_slam_system_test, df_slam_tracker_test,
  # df_dynamics_test and df_object_maps_short_test. DF_ASAN_EXCLUDE='' bash deploy/test.sh runs
  # them too.
  exclude="${DF_ASAN_EXCLUDE-df_slam_accuracy_test|df_sim_sequence_test|df_slam_checkpoint_test|df_dynamic_accuracy_test|df_object_maps_test}"
  unit_filter=(-LE "integration|hostile" -E "^roudi_${exclude:+|^($exclude)\$}")
  mapfile -t unit_tests < <(ctest --test-dir "$asan" -N "${unit_filter[@]}" |
    sed -n 's/^ *Test *#[0-9]*: *//p')
  ninja -C "$asan" "${unit_tests[@]}" df_fuzzers
  ASAN_OPTIONS="detect_leaks=1:abort_on_error=1" \
    LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp:print_suppressions=0" \
    UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    ctest --test-dir "$asan" "${unit_filter[@]}" --output-on-failure -j "${DF_TEST_JOBS:-2}"
  bash "$root/fuzz/run_targets.sh" "$asan" "${DF_FUZZ_SECONDS:-20}"
fi
