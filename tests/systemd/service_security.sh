#!/usr/bin/env bash
# systemd/gvsd.service must score 2.0 or lower in
# `systemd-analyze security --offline=yes` and keep the
# options the daemon depends on. Prints the score.
set -euo pipefail
unit=$1
command -v systemd-analyze >/dev/null || { echo "FAIL: systemd-analyze not installed (apt-get install systemd)"; exit 1; }
out=$(systemd-analyze security --offline=yes "$unit" 2>&1) || true
score=$(grep -o 'Overall exposure level for gvsd.service: [0-9.]*' <<<"$out" | awk '{print $NF}')
[[ -n "$score" ]] || { echo "FAIL: no score in:"; echo "$out"; exit 1; }
echo "gvsd.service exposure: $score"
# --threshold is on systemd's internal 0-100 scale: 20 = 2.0.
systemd-analyze security --offline=yes --threshold=20 "$unit" >/dev/null 2>&1 ||
  { echo "FAIL: exposure $score is above 2.0"; exit 1; }
for need in 'Type=notify' 'WatchdogSec=' 'Restart=on-failure' 'User=gvsd' 'LimitRTPRIO=' 'LimitMEMLOCK=' \
            'RestrictRealtime=no' 'CapabilityBoundingSet=CAP_SYS_NICE CAP_IPC_LOCK' \
            'RestrictAddressFamilies=AF_CAN AF_UNIX AF_NETLINK' 'DeviceAllow=char-gpiochip rw' \
            'DeviceAllow=char-video4linux rw' 'DeviceAllow=char-dma_heap rw' 'ProtectSystem=strict'; do
  grep -qxF "$need" "$unit" || grep -q "^${need}" "$unit" || { echo "FAIL: $unit lacks '$need'"; exit 1; }
done
# The syscall filter must leave what gvsd calls (SCHED_FIFO, affinity,
# mlockall, the absolute sleep): in @system-service, in none of the denied sets.
expand() { systemd-analyze syscall-filter "$@" | sed -n 's/^ \+\([a-z_0-9@-]\+\)$/\1/p'; }
allowed=$(expand @system-service; expand $(expand @system-service | grep '^@'))
denied=$(expand $(sed -n 's/^SystemCallFilter=~//p' "$unit"))
for call in sched_setscheduler sched_setaffinity mlockall clock_nanosleep socket sendto; do
  grep -qx "$call" <<<"$allowed" || { echo "FAIL: $call is not in @system-service"; exit 1; }
  if grep -qx "$call" <<<"$denied"; then echo "FAIL: the unit denies $call, which gvsd needs"; exit 1; fi
done
echo "OK"
