#!/bin/sh
# Inside the qemu guest (see gvsd_vcan.sh): gvs monitor listens on vcan0
# while gvsd sends for 4 s (start-up under emulation takes up to a minute);
# prints the monitor's last view while gvsd sent (the summary, taken after
# gvsd stopped, shows its values as old) and the summary.
# usage: gvsd_vcan_guest.sh GVS GVSD DATASET CONFIG
"$1" monitor vcan0 --seconds 300 --plain > "$GVS_BENCH_OUT/monitor.txt" 2>&1 &
monitor=$!
# The external distance sensor: 62.00 mm (raw 6200 = 0x1838, Motorola) every 2 ms.
cangen vcan0 -I 520 -L 2 -D 1838 -g 2 &
sensor=$!
sleep 2
if ! "$2" --config "$4" --source "replay:$3" --can socketcan:vcan0 --run-for 4 2> "$GVS_BENCH_OUT/gvsd.err"; then
  kill -TERM "$sensor"
  cat "$GVS_BENCH_OUT/gvsd.err"
  exit 1
fi
# gvsd sent its last frame: stop the sensor and the monitor (it prints its summary on SIGTERM).
kill -TERM "$sensor"
sleep 1
kill -TERM "$monitor"
wait "$monitor"
echo "--- gvsd log (tail) ---"
tail -n 8 "$GVS_BENCH_OUT/gvsd.err"
echo "--- gvs monitor while gvsd sent (last view with valid values) ---"
grep "^speed .*valid yes" "$GVS_BENCH_OUT/monitor.txt" | tail -n 1
grep "^height .*mm  valid yes .*scale: external height" "$GVS_BENCH_OUT/monitor.txt" | tail -n 1
echo "--- gvs monitor summary ---"
tail -n 16 "$GVS_BENCH_OUT/monitor.txt"
