#!/usr/bin/env bash
# Transport benchmark (docs/benchmarks.md): starts a RouDi for the run unless one runs.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${DF_BUILD:-$root/build}/bin/df_bench_transport"
state="$(mktemp)"
bash "$root/tests/integration/roudi_ctl.sh" start "$root/deploy/config/roudi.toml" "$state" >/dev/null
trap 'bash "$root/tests/integration/roudi_ctl.sh" stop "$root/deploy/config/roudi.toml" "$state" >/dev/null' EXIT
"$bin" "$@"
