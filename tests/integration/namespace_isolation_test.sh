#!/usr/bin/env bash
# Two pipelines on one machine differ by their namespace (DF_NS, dds.ns), which is part of every
# topic's name ("<ns>/frames"). This Cyclone leaks samples across domains and partitions over
# shared memory (FACTS.md, section 2: a reader in another partition got every frame, and one in
# another domain held every chunk until the writer ran out after 64 frames). Topics whose names
# differ never match. Capture plays 150 frames, more than the pool's 64 chunks, in namespace A.
# Asserts, over shared memory and over UDP: a reader in namespace A gets them, and a reader of
# the same topic in namespace B, in another process, gets none.
source "$(dirname "$0")/lib.sh"
N=150
make_sequence $N --no-models
for transport in shm udp; do
  A="${NS}_a_$transport"; B="${NS}_b_$transport"
  "$BIN/df_tap" --transport $transport echo "$B/frames" --items 0 --duration 30 --idle 30 \
    >"$TMP/b_$transport.txt" 2>"$TMP/b_$transport.err" &
  b_pid=$!; pids+=($b_pid)
  "$BIN/df_tap" --transport $transport --wait 30 echo "$A/frames" --items 0 --idle 5 \
    >"$TMP/a_$transport.txt" 2>"$TMP/a_$transport.err" &
  a_pid=$!; pids+=($a_pid)
  sleep 2  # the readers discover each other's absence; capture finds the A reader
  "$BIN/df_capture" "$TMP/seq" --config "$SRC/deploy/config/capture_realtime.pbtxt" \
    --set "dds { ns: \"$A\" transport: \"$transport\" }" --set "loops: 1" \
    >"$TMP/capture_$transport.log" 2>&1 || fail "capture ($transport) failed: $(tail -3 "$TMP/capture_$transport.log")"
  wait $a_pid || true
  kill $b_pid 2>/dev/null || true; wait $b_pid 2>/dev/null || true
  if [ $transport = shm ]; then
    grep -q "frames .*shared memory, loaned" "$TMP/capture_$transport.log" ||
      fail "capture did not write its frames to shared memory: $(grep "writer .*frames" "$TMP/capture_$transport.log")"
  fi
  got_a=$(grep -c "^header:" "$TMP/a_$transport.txt" || true)
  got_b=$(grep -c "^header:" "$TMP/b_$transport.txt" || true)
  [ "$got_a" -ge $((N / 2)) ] ||
    fail "$transport: the reader in namespace A got $got_a of $N frames ($(tail -2 "$TMP/a_$transport.err"))"
  [ "$got_b" -eq 0 ] || fail "$transport: the reader in namespace B got $got_b frames of namespace A"
  ! grep -qi "loan.*fail\|pool.*exhaust" "$TMP/capture_$transport.log" ||
    fail "$transport: capture's loans failed: $(grep -i "loan.*fail\|pool.*exhaust" "$TMP/capture_$transport.log" | head -2)"
  pass "$transport: namespace A's reader got $got_a of $N frames, namespace B's reader none"
done
