#!/usr/bin/env bash
# Runs every fuzz target of a DF_FUZZ build over its corpus, then fuzzes it for SECONDS.
#   fuzz/run_targets.sh BUILD_DIR SECONDS [TARGET...]
# Corpora: BUILD_DIR/fuzz/seeds/<target> (written by df_fuzz_seeds, never changed) and
# BUILD_DIR/fuzz/corpus/<target> (what the fuzzer found, kept between runs). A crashing input
# is saved as BUILD_DIR/fuzz/findings/<target>/crash-*. fuzz/corpus/<target> (in the repository:
# the long runs' corpora, minimised with -merge=1) is read as well, so every run replays them.
# Prints one line per target:
#   <target> seconds=<s> executions=<n> corpus=<files> crashes=<n>
# and exits 1 if any target crashed or stopped with an error.
# Environment:
#   DF_FUZZ_LEDGER=FILE   append one tab-separated line per target run to FILE (fuzz/hours.tsv
#                         is the project's ledger; fuzz/hours.sh adds it up): date (UTC), target,
#                         wall seconds, CPU seconds, executions, crashes, corpus files, commit
#                         ($DF_FUZZ_COMMIT: the one the targets were built from; run_fuzz.sh
#                         sets it, "+changes" when the checkout had uncommitted edits)
#   DF_FUZZ_NO_SEEDS=1    do not rewrite the seed corpora (they exist; another run may read them)
set -uo pipefail
build="$(cd "${1:?usage: run_targets.sh BUILD_DIR SECONDS [TARGET...]}" && pwd)"
seconds="${2:?seconds per target}"
shift 2
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(fuzz_samples fuzz_tum_lists fuzz_tum_images fuzz_mcap fuzz_ply fuzz_config)
fi
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bin="$build/fuzz"
if [ "${DF_FUZZ_NO_SEEDS:-0}" != 1 ] || [ ! -d "$bin/seeds" ]; then
  "$bin/df_fuzz_seeds" "$bin/seeds" >/dev/null || { echo "df_fuzz_seeds failed"; exit 1; }
fi
commit="${DF_FUZZ_COMMIT:-$(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown)}"
# Leaks inside third-party libraries (protobuf, OpenCV, Cyclone) are not findings of ours.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$here/lsan.supp:print_suppressions=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
count_findings() {
  find "$1" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'oom-*' -o -name 'timeout-*' \
    -o -name 'leak-*' \) | wc -l
}
failed=0
for t in "${targets[@]}"; do
  corpus="$bin/corpus/$t" findings="$bin/findings/$t" log="$bin/logs/$t.log"
  mkdir -p "$corpus" "$findings" "$(dirname "$log")"
  before=$(count_findings "$findings")
  kept=()
  if [ -d "$here/corpus/$t" ]; then kept=("$here/corpus/$t"); fi
  # Per run (another run over the same build may be writing its own): the log goes to
  # logs/<target>.log when the run is over.
  times="$(mktemp)" run_log="$(mktemp "$log.XXXXXX")"
  # -max_len 64 KiB: room for small images and MCAP files; -rss_limit_mb also limits a single
  # allocation, so an input that makes a reader allocate gigabytes is a finding. Wall and CPU
  # seconds of the run come from /usr/bin/time (the CPU share is small under nice on a busy host).
  /usr/bin/time -f '%e %U %S' -o "$times" \
    "$bin/$t" "$corpus" "$bin/seeds/$t" "${kept[@]}" -max_total_time="$seconds" -max_len=65536 \
    -timeout=20 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$findings/" \
    >"$run_log" 2>&1
  rc=$?
  mv -f "$run_log" "$log"
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  crashes=$(( $(count_findings "$findings") - before ))
  if [ "$rc" -ne 0 ] && [ "$crashes" -eq 0 ]; then
    crashes=1  # stopped with an error but wrote no input (e.g. a report at start-up)
  fi
  files=$(find "$corpus" -type f | wc -l)
  read -r wall user sys < <(tail -1 "$times") || true
  rm -f "$times"
  cpu=$(awk -v u="${user:-0}" -v s="${sys:-0}" 'BEGIN { printf "%.1f", u + s }')
  wall=$(awk -v w="${wall:-0}" 'BEGIN { printf "%.1f", w }')
  echo "$t seconds=$wall cpu_seconds=$cpu executions=${execs:-?} corpus=$files crashes=$crashes rc=$rc"
  if [ -n "${DF_FUZZ_LEDGER:-}" ]; then
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "$t" "$wall" \
      "$cpu" "${execs:-0}" "$crashes" "$files" "$commit" >>"$DF_FUZZ_LEDGER"
  fi
  if [ "$rc" -ne 0 ] || [ "$crashes" -gt 0 ]; then
    failed=1
    echo "  see $log and $findings/"
    grep -m5 -E "ERROR|runtime error|property broken|SUMMARY" "$log" | sed 's/^/  /'
  fi
done
exit $failed
