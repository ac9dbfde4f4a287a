#!/usr/bin/env bash
# Fuzzing as a benchmark: builds the fuzz targets (clang, ASan + UBSan) and fuzzes each target,
# recording every run in the ledger fuzz/hours.tsv so hours add up across runs and sessions
# (fuzz/hours.sh prints the totals for docs/hardening.md, "Fuzzing").
#   bash tests/bench/run_fuzz.sh SECONDS [TARGET...]          each target SECONDS more
#   bash tests/bench/run_fuzz.sh --until SECONDS [TARGET...]  each target until its ledger total
#                                                             reaches SECONDS (3600: one hour)
# Targets run in turns of DF_FUZZ_SLICE seconds (default 600), so a run that is stopped loses at
# most one turn of its record, and DF_FUZZ_JOBS targets (default 2) fuzz at a time. Run it under
# `nice -n 19` on a shared machine. Build folder: $DF_BUILD_FUZZ (default build-fuzz); corpora
# accumulate there between runs. Exits 1 if any target crashed (its turns then stop; the input is
# in <build>/fuzz/findings/<target>/).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
until_total=0
if [ "${1:-}" = --until ]; then
  until_total=1
  shift
fi
seconds="${1:?usage: run_fuzz.sh [--until] SECONDS [TARGET...]}"
shift
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(fuzz_samples fuzz_tum_lists fuzz_tum_images fuzz_mcap fuzz_ply fuzz_config)
fi
slice="${DF_FUZZ_SLICE:-600}"
jobs="${DF_FUZZ_JOBS:-2}"
export DF_FUZZ_LEDGER="${DF_FUZZ_LEDGER:-$root/fuzz/hours.tsv}"
build="${DF_BUILD_FUZZ:-$root/build-fuzz}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -gline-tables-only" "-DCMAKE_C_FLAGS_RELEASE=-O1 -gline-tables-only" \
    -DDF_SANITIZE=address,undefined -DDF_FUZZ=ON -DDF_BUILD_BENCHMARKS=OFF >/dev/null
fi
ninja -C "$build" df_fuzzers
# The ledger names the commit the fuzz targets were just built from (the checkout may move on).
DF_FUZZ_COMMIT="$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
if [ -n "$(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null)" ]; then
  DF_FUZZ_COMMIT+="+changes"
fi
export DF_FUZZ_COMMIT
"$build/fuzz/df_fuzz_seeds" "$build/fuzz/seeds" >/dev/null
export DF_FUZZ_NO_SEEDS=1

# Seconds still to run per target: SECONDS, or SECONDS less what the ledger already holds.
declare -A left
for t in "${targets[@]}"; do
  done_s=0
  if [ "$until_total" = 1 ] && [ -f "$DF_FUZZ_LEDGER" ]; then
    done_s=$(awk -F'\t' -v t="$t" 'NR > 1 && $2 == t { s += $3 } END { printf "%d", s }' \
      "$DF_FUZZ_LEDGER")
  fi
  left[$t]=$(( seconds - done_s > 0 ? seconds - done_s : 0 ))
  echo "$t: ${left[$t]} s to run"
done

# Worker j takes targets j, j+jobs, ... and runs them in turns until each has had its seconds.
worker() {
  local mine=("$@") t n crashed=0
  declare -A rest
  for t in "${mine[@]}"; do rest[$t]=${left[$t]}; done
  while :; do
    local busy=0
    for t in "${mine[@]}"; do
      [ "${rest[$t]}" -gt 0 ] || continue
      busy=1
      n=$(( rest[$t] < slice ? rest[$t] : slice ))
      if ! bash "$root/fuzz/run_targets.sh" "$build" "$n" "$t"; then
        crashed=1
        rest[$t]=0
        continue
      fi
      rest[$t]=$(( rest[$t] - n ))
    done
    [ "$busy" = 1 ] || break
  done
  return $crashed
}
start=$(date +%s)
pids=()
for (( j = 0; j < jobs; j++ )); do
  mine=()
  for (( i = j; i < ${#targets[@]}; i += jobs )); do mine+=("${targets[$i]}"); done
  [ ${#mine[@]} -gt 0 ] || continue
  worker "${mine[@]}" &
  pids+=($!)
done
rc=0
for p in "${pids[@]}"; do wait "$p" || rc=1; done
echo "total wall time: $(( $(date +%s) - start )) s"
bash "$root/fuzz/hours.sh" "$DF_FUZZ_LEDGER"
exit $rc
