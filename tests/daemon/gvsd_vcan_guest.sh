#!/bin/sh
# Inside the qemu guest (see gvsd_vcan.sh): gvs monitor listens on vcan0
# while gvsd sends for 4 s (start-up under emulation takes up to a minute);
# prints the monitor's last view while gvsd sent (the summary, taken after
# gvsd stopped, shows its values as old) and the summary.
# usage: gvsd_vcan_guest.sh GVS GVSD DATASET CONFIG
"$1" monitor vcan0 --seconds 300 --plain > "$GVS_BENCH_OUT/monitor.txt" 2>&1 &
monitor=$!
sleep 2
if ! "$2" --config "$4" --source "replay:$3" --can socketcan:vcan0 --run-for 4 2> "$GVS_BENCH_OUT/gvsd.err"; then
  cat "$GVS_BENCH_OUT/gvsd.err"
  exit 1
fi
# gvsd sent its last frame: stop the monitor (it prints its summary on SIGTERM).
sleep 1
kill -TERM "$monitor"
wait "$monitor"
echo "--- gvsd log (tail) ---"
tail -n 8 "$GVS_BENCH_OUT/gvsd.err"
echo "--- gvs monitor while gvsd sent (last view with valid values) ---"
grep "^speed .*valid yes" "$GVS_BENCH_OUT/monitor.txt" | tail -n 1
echo "--- gvs monitor summary ---"
tail -n 16 "$GVS_BENCH_OUT/monitor.txt"
