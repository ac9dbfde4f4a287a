#!/usr/bin/env bash
# Our Foxglove WebSocket server (df_foxglove_ws) with the real client Foxglove Studio uses
# (@foxglove/ws-protocol over `ws`, tests/js/ws_client_check.mjs): the client subscribes, sees the
# advertised schema name and encodings, and receives the published payload bytes intact.
# Usage: foxglove_ws_js_test.sh PATH/TO/df_ws_js_test_server
source "$(dirname "$0")/lib.sh"
server_bin="${1:?usage: $0 PATH/TO/df_ws_js_test_server}"
command -v node >/dev/null || fail "node not found: run deploy/setup.sh"
[ -d "$SRC/tests/js/node_modules/@foxglove/ws-protocol" ] && [ -d "$SRC/tests/js/node_modules/ws" ] \
  || fail "tests/js has no @foxglove/ws-protocol or ws: run deploy/setup.sh (npm ci in tests/js)"

: >"$TMP/server.out"  # made here: the loop below may read it before the server writes
"$server_bin" --timeout-s 30 >"$TMP/server.out" 2>"$TMP/server.err" &
server=$!; pids+=($server)
port=""
for _ in $(seq 100); do
  port=$(sed -n 's/^port \([0-9][0-9]*\)$/\1/p' "$TMP/server.out")
  [ -n "$port" ] && break
  kill -0 $server 2>/dev/null || break
  sleep 0.1
done
[ -n "$port" ] || fail "the test server printed no port: $(cat "$TMP/server.err")"
pass "server listening on port $port"

node "$SRC/tests/js/ws_client_check.mjs" "ws://127.0.0.1:$port" >"$TMP/client.out" 2>"$TMP/client.err" \
  || fail "@foxglove/ws-protocol client: $(cat "$TMP/client.err") (server: $(tail -5 "$TMP/server.err"))"
pass "client: $(cat "$TMP/client.out")"
wait $server || fail "the test server exited with $?: $(tail -5 "$TMP/server.err")"
pass "server saw every message written and the client close"
