#!/bin/sh
# gvs-vcan.sh up|down [IFACE] — a virtual CAN bus for bench work on a laptop
# (no hardware): loads vcan, creates IFACE (default vcan0) and raises it.
# Used by gvs-vcan.service; runs as root.
set -eu
action="${1:-up}"
iface="${2:-vcan0}"
case "$action" in
  up)
    for m in vcan can_raw; do
      modprobe "$m" 2>/dev/null || [ -d "/sys/module/$m" ] ||
        { echo "gvs-vcan: cannot load kernel module $m (is this kernel built with CAN support?)" >&2; exit 1; }
    done
    ip link show "$iface" >/dev/null 2>&1 || ip link add dev "$iface" type vcan
    ip link set "$iface" up
    # A longer TX queue than vcan's default of 1000 frames is not needed at
    # gvs rates (about 110 frames/s); leave it.
    ip -details link show "$iface"
    ;;
  down)
    ip link show "$iface" >/dev/null 2>&1 && ip link del dev "$iface"
    ;;
  *)
    echo "usage: $0 up|down [IFACE]" >&2
    exit 2
    ;;
esac
