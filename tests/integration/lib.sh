# Shared helpers of the shell integration tests.
set -euo pipefail
BIN="${DF_TEST_BIN:?}"; SRC="${DF_TEST_SRC:?}"
TMP="$(mktemp -d "${TMPDIR:-/tmp}/dftest-XXXXXX")"
NS="t$$_${RANDOM}"
pids=()
cleanup() {
  for p in "${pids[@]:-}"; do [ -n "$p" ] && kill "$p" 2>/dev/null || true; done
  [ -n "${DF_KEEP_TEST_FILES:-}" ] || rm -rf "$TMP"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
pass() { echo "ok: $*"; }
roudi_running() { [ -e /tmp/roudi.lock ] && ! flock -n /tmp/roudi.lock true; }
