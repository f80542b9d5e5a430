#!/bin/sh
# Runs under a real systemd (PID 1): in a systemd-nspawn container on this
# machine's kernel and CPU (service_nspawn.sh, mode "native") or in a qemu
# guest with Debian's kernel and vcan0 (service_in_qemu.sh, mode "emulated").
# Installs the gvs package, starts gvsd.service on the simulated camera, then
#   1. kills gvsd with SIGKILL: systemd restarts it; measured from the kill to
#      the first valid GVS_Velocity frame sent by the new process;
#   2. stops gvsd's sender thread alone (gvs_freeze_thread), as a hung thread:
#      the watchdog must fire (journal "Watchdog timeout"), systemd restarts
#      it, valid again.
# native: the car's timing is asserted (valid within 2 s of SIGKILL, the
# watchdog within 2 s of the hang); gvsd writes its frames to a candump file
# (this kernel has no CAN). emulated: every instruction is emulated (20-50x
# slower), so times are reported, not asserted; gvsd sends on vcan0 under the
# unit's whole sandbox (AF_CAN, devices) and candump listens.
# usage: service_restart_check.sh native|emulated DEB FREEZE_TOOL
set -u
mode=$1 deb=$2 freeze=$3
out=${GVS_BENCH_OUT:-/tmp}
bus=$out/bus.log

fail() {
  echo "FAIL: $*"
  echo "--- journal of gvsd.service (tail) ---"
  journalctl -u gvsd.service --no-pager -o short-monotonic | tail -n 25
  exit 1
}
now() { date +%s.%N; }
seconds() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", b - a }'; }
at_most() { awk -v a="$1" -v l="$2" 'BEGIN { exit !(a >= 0 && a <= l) }'; }
# First GVS_Velocity frame (0x300) with GVS_Valid (bit 12 = bit 4 of byte 1)
# logged after time $1 (the newest 400 lines); prints its timestamp.
first_valid_after() {
  tail -n 400 "$bus" 2>/dev/null | awk -v t="$1" '
    { ts = substr($1, 2, length($1) - 2) + 0
      split($3, f, "#"); if (f[1] != "300" || ts <= t) next
      hi = index("0123456789ABCDEF", toupper(substr(f[2], 3, 1))) - 1
      if (hi % 2 == 1) { printf "%.6f\n", ts; exit } }'
}
# Waits up to $2 s for a valid frame after time $1; prints its timestamp.
wait_valid_after() {
  i=0
  while [ "$i" -lt $(($2 * 20)) ]; do
    v=$(first_valid_after "$1")
    [ -n "$v" ] && { echo "$v"; return 0; }
    sleep 0.05; i=$((i + 1))
  done
  return 1
}
main_pid() { systemctl show -p MainPID --value gvsd.service; }
restarts() { systemctl show -p NRestarts --value gvsd.service; }
# When process $1 was created (fork by systemd), as a `date +%s.%N` time;
# /proc/PID/stat field 22 counts clock ticks since boot.
started_at() {
  awk -v up="$(cut -d' ' -f1 /proc/uptime)" -v n="$(now)" -v hz="$(getconf CLK_TCK)" \
    '{ printf "%.3f", n - (up - $22 / hz) }' "/proc/$1/stat"
}
# Waits up to $2 s for a main process other than $1; prints its PID.
wait_new_main_pid() {
  i=0
  while [ "$i" -lt $(($2 * 20)) ]; do
    p=$(main_pid)
    [ "$p" != "$1" ] && [ "$p" != 0 ] && { echo "$p"; return 0; }
    sleep 0.05; i=$((i + 1))
  done
  return 1
}

echo "systemd $(systemctl --version | head -1 | cut -d' ' -f2) as PID 1 ($(ps -p 1 -o comm=)), kernel $(uname -r), mode $mode"
dpkg -i "$deb" > "$out/dpkg.log" 2>&1 || { cat "$out/dpkg.log"; fail "dpkg -i $(basename "$deb")"; }
id gvsd > /dev/null || fail "the package did not create the gvsd user"
echo "installed $(dpkg-query -W -f '${Package} ${Version}' gvs); user: $(id gvsd)"

mkdir -p /etc/systemd/system/gvsd.service.d
if [ "$mode" = native ]; then
  # The packaged unit unchanged but for one writable path, for the log.
  chmod 0777 "$out"
  printf '[Service]\nReadWritePaths=%s\n' "$out" > /etc/systemd/system/gvsd.service.d/test.conf
  # The simulator's default camera (512x384, 60 fps) with the double-pulse
  # strobe, gvsd's default: a speed from the first frames on, so the check
  # after each restart sees valid speeds at once.
  cat > /etc/gvsd/gvsd.toml <<EOF
[source]
uri = "sim:sine"
[can]
uri = "candump:$bus"
[exposure]
mode = "double-pulse"
EOF
  limit_first_s=30 limit_kill_s=2 limit_watchdog_s=2
else
  # An emulated CPU: small simulated frames at 20 fps, the simulator's truth
  # in place of the estimator and a 300 ms staleness limit, so that the new
  # process's estimates are fresh on the bus; the first start may take minutes.
  printf '[Service]\nTimeoutStartSec=300s\n' > /etc/systemd/system/gvsd.service.d/test.conf
  cat > /etc/gvsd/gvsd.toml <<'EOF'
[source]
uri = "sim:sine"
sim_fps = 20.0
[can]
uri = "socketcan:vcan0"
staleness_limit_ms = 300.0
[camera]
width_px = 64
height_px = 48
mm_per_px = 0.8
[estimator]
method = "truth"
EOF
  candump -L vcan0,300:7FF > "$bus" 2>&1 &
  limit_first_s=300 limit_kill_s=120 limit_watchdog_s=10
fi
systemctl daemon-reload
gvsd --check-config --config /etc/gvsd/gvsd.toml || fail "gvsd refuses the test configuration"

t_start=$(now)
systemctl start gvsd.service || fail "systemctl start gvsd"
v=$(wait_valid_after "$t_start" "$limit_first_s") || fail "no valid velocity within $limit_first_s s of the first start"
echo "first start: valid after $(seconds "$t_start" "$v") s"
systemctl show -p User -p Type -p WatchdogUSec -p Restart -p RestartUSec gvsd.service | tr '\n' ' '; echo
ps -L -o tid=,comm=,cls=,rtprio= -p "$(main_pid)" | sed 's/^/  thread /'

# 1. SIGKILL: systemd restarts it (Restart=on-failure, RestartSec=200ms).
sleep 3
pid=$(main_pid); n0=$(restarts)
t_kill=$(now); kill -KILL "$pid"
new_pid=$(wait_new_main_pid "$pid" 10) || fail "no new main process within 10 s of SIGKILL"
t_fork=$(started_at "$new_pid")
v=$(wait_valid_after "$t_fork" "$limit_kill_s") || fail "no valid velocity from the new process within $limit_kill_s s"
kill_s=$(seconds "$t_kill" "$v")
[ "$(restarts)" -eq $((n0 + 1)) ] || fail "NRestarts went from $n0 to $(restarts), expected one restart"
journalctl -u gvsd.service --no-pager | grep -q 'status=9/KILL' || fail "journal does not show the kill"
echo "SIGKILL: new gvsd started by systemd after $(seconds "$t_kill" "$t_fork") s, valid on the bus after $kill_s s"

# 2. Hung sender thread: the watchdog stops being fed, systemd kills and restarts.
sleep 3
pid=$(main_pid); n0=$(restarts)
"$freeze" "$pid" gvsd-sender 60 > "$out/freeze.log" 2>&1 &
freezer=$!
while ! grep -q stopped "$out/freeze.log"; do
  kill -0 "$freezer" 2>/dev/null || { cat "$out/freeze.log"; fail "gvs_freeze_thread"; }
  sleep 0.01
done
t_freeze=$(now)
new_pid=$(wait_new_main_pid "$pid" 30) || fail "no restart within 30 s of stopping the sender thread"
t_fork=$(started_at "$new_pid")
cat "$out/freeze.log"
journalctl -u gvsd.service --no-pager | grep -q 'Watchdog timeout' || fail "journal shows no watchdog timeout"
t_wd=$(journalctl -u gvsd.service --no-pager -o short-unix | awk '/Watchdog timeout/ { t = $1 } END { print t }')
v=$(wait_valid_after "$t_fork" "$limit_kill_s") || fail "no valid velocity after the watchdog restart"
kill "$freezer" 2>/dev/null; wait "$freezer" 2>/dev/null
wd_s=$(seconds "$t_freeze" "$t_wd")
echo "hung sender thread: watchdog timeout after $wd_s s (WatchdogSec=1s), valid on the bus again after $(seconds "$t_freeze" "$v") s"
journalctl -u gvsd.service --no-pager | grep -E 'Watchdog timeout|status=9/KILL|Killing process|restart counter' | sed 's/^/  journal: /'
[ "$(restarts)" -eq $((n0 + 1)) ] || fail "NRestarts went from $n0 to $(restarts), expected one restart"

at_most "$kill_s" "$limit_kill_s" || fail "valid $kill_s s after SIGKILL: over $limit_kill_s s"
at_most "$wd_s" "$limit_watchdog_s" || fail "watchdog fired $wd_s s after the hang: over $limit_watchdog_s s"
echo "guest: all checks passed"
