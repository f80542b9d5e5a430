#!/bin/sh
# vcan-demo.sh BUILD_DIR — the bench demo of docs/bench.md, run on a vcan0
# (inside tests/bench/qemu-vcan.sh or on a laptop, as root): re-creates vcan0
# with systemd/gvs-vcan.sh, records the bus with candump -L while
# gvs_can_vcan_bench sends gvs traffic, then summarises the log with gvs monitor.
set -e
build="${1:?usage: vcan-demo.sh BUILD_DIR}"
systemd/gvs-vcan.sh down vcan0
systemd/gvs-vcan.sh up vcan0 >/dev/null
echo "vcan0 re-created by systemd/gvs-vcan.sh"
candump -L vcan0 > /tmp/bus.log &
sleep 0.5
"$build/tests/can/gvs_can_vcan_bench" traffic vcan0 | tail -1
sleep 0.3
kill $!
echo "candump -L lines: $(wc -l < /tmp/bus.log)"
head -4 /tmp/bus.log
"$build/bin/gvs" monitor /tmp/bus.log
