#!/usr/bin/env bash
# The detector run as another user (nobody, whose home holds no model) finds the YOLOv5s model
# that deploy/setup.sh installed for every user, loads it and waits for frames.
source "$(dirname "$0")/lib.sh"
sys_model=/usr/local/share/detectfusion/models/yolov5s
if [ "$(id -u)" -ne 0 ] || [ ! -f "$sys_model/model.json" ]; then
  echo "SKIP: needs root (to switch user) and the model in $sys_model (bash deploy/setup.sh)"
  exit 77
fi
chmod 755 "$TMP"
log="$TMP/detector.log"
# nobody's HOME is /nonexistent: no ~/.cache model; DF_MODELS_DIR unset.
env -u DF_MODELS_DIR HOME=/nonexistent setpriv --reuid=nobody --regid=nogroup --clear-groups \
  "$BIN/df_detector" --set "dds { ns: \"$NS\" transport: \"udp\" }" >"$log" 2>&1 &
pids+=($!)
for _ in $(seq 600); do
  grep -q "waiting for frames" "$log" && break
  kill -0 "${pids[-1]}" 2>/dev/null || break
  sleep 0.1
done
grep -q "YOLO $sys_model at .*waiting for frames" "$log" \
  || fail "df_detector as nobody did not load $sys_model: $(tail -5 "$log")"
pass "df_detector as user nobody loaded $sys_model"
