#!/usr/bin/env bash
# Adds up the fuzzing ledger (fuzz/hours.tsv, one line per run of a target, appended by
# fuzz/run_targets.sh when DF_FUZZ_LEDGER is set): per target the runs, wall hours, CPU hours,
# executions and crashes so far, as a Markdown table for docs/hardening.md ("Fuzzing").
#   fuzz/hours.sh [LEDGER]
set -euo pipefail
ledger="${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/hours.tsv}"
awk -F'\t' '
  $2 == "target" { next }  # the header line
  {
    if (!($2 in runs)) order[++n] = $2
    runs[$2]++; wall[$2] += $3; cpu[$2] += $4; execs[$2] += $5; crashes[$2] += $6
    last[$2] = $1
  }
  END {
    print "| target | runs | wall hours | CPU hours | executions | crashes | last run (UTC) |"
    print "|---|---:|---:|---:|---:|---:|---|"
    for (i = 1; i <= n; i++) {
      t = order[i]
      printf "| %s | %d | %.2f | %.2f | %d | %d | %s |\n", t, runs[t], wall[t] / 3600,
             cpu[t] / 3600, execs[t], crashes[t], last[t]
    }
  }' "$ledger"
