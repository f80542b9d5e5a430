#!/bin/sh
# Inside the qemu guest (see gvsd_gpio_sim.sh): gvsd fires each frame's
# exposure plan on the simulated chip. Checks, independently of gvsd's own
# counters, that the LED line was seen both on and off while gvsd ran, that
# gvsd's lines carried its consumer name, and that both lines are released
# and off afterwards; then that gvsd's final health line reports a plan per
# captured frame, 4 edges per plan (trigger on/off, LED on/off) and no errors.
# usage: gvsd_gpio_sim_guest.sh GVSD DATASET
set -u
gvsd=$1 dataset=$2
out="$GVS_BENCH_OUT"
cat > /tmp/gvsd-gpio.toml <<TOML
[estimator]
method = "truth"
[exposure]
mode = "fixed"
initial_us = 3000.0
[light]
driver = "gpio"
chip = "$GVS_GPIO_SIM_CHIP"
led_line = 1
trigger_line = 0
consumer = "gvsd-test"
TOML
"$gvsd" --config /tmp/gvsd-gpio.toml --source "replay:$dataset" --can candump:/dev/null --run-for 4 \
  > "$out/gvsd.out" 2> "$out/gvsd.err" &
pid=$!
on=0 off=0 consumer=""
while kill -0 "$pid" 2> /dev/null; do
  v=$(cat "$GVS_GPIO_SIM_SYSFS/sim_gpio1/value")
  if [ "$v" = 1 ]; then on=$((on + 1)); else off=$((off + 1)); fi
  [ -n "$consumer" ] || consumer=$(gpioinfo "$GVS_GPIO_SIM_CHIP" 2> /dev/null | grep -o '"gvsd-test"' | head -1)
done
wait "$pid"; rc=$?
grep -E "light and trigger|health:" "$out/gvsd.err" | tail -n 2
echo "LED line samples while gvsd ran: on $on, off $off; consumer seen: ${consumer:-none}"
after=$(gpioinfo "$GVS_GPIO_SIM_CHIP" | grep -c unused)
echo "after gvsd: LED $(cat "$GVS_GPIO_SIM_SYSFS/sim_gpio1/value"), trigger $(cat "$GVS_GPIO_SIM_SYSFS/sim_gpio0/value"), unused lines $after of 4"
fail=0
[ "$rc" = 0 ] || { echo "FAIL: gvsd exited with $rc"; tail -n 5 "$out/gvsd.err"; fail=1; }
[ "$on" -gt 0 ] && [ "$off" -gt 0 ] || { echo "FAIL: the LED line was not seen both on and off"; fail=1; }
[ "$consumer" = '"gvsd-test"' ] || { echo "FAIL: gpioinfo did not show gvsd's consumer name"; fail=1; }
[ "$after" = 4 ] || { echo "FAIL: gvsd did not release its lines"; fail=1; }
[ "$(cat "$GVS_GPIO_SIM_SYSFS/sim_gpio1/value")" = 0 ] || { echo "FAIL: the LED line is left on"; fail=1; }
health=$(grep "health:" "$out/gvsd.err" | tail -n 1)
frames=$(echo "$health" | sed -n 's/.*health: capture \([0-9]*\) frames.*/\1/p')
plans=$(echo "$health" | sed -n 's/.* light \([0-9]*\) plans, \([0-9]*\) edges, .* errors \([0-9]*\) .*/\1/p')
edges=$(echo "$health" | sed -n 's/.* light \([0-9]*\) plans, \([0-9]*\) edges, .* errors \([0-9]*\) .*/\2/p')
errors=$(echo "$health" | sed -n 's/.* light \([0-9]*\) plans, \([0-9]*\) edges, .* errors \([0-9]*\) .*/\3/p')
echo "gvsd: $frames frames captured, $plans plans fired, $edges edges, $errors errors"
if [ -z "$plans" ] || [ -z "$frames" ]; then
  echo "FAIL: no light counters in gvsd's health line"; fail=1
else
  # One plan per frame (the last plan may have been fired for a frame the stop cut off).
  [ "$plans" -ge "$frames" ] && [ "$plans" -le $((frames + 1)) ] || { echo "FAIL: $plans plans for $frames frames"; fail=1; }
  [ "$edges" = $((4 * plans)) ] || { echo "FAIL: $edges edges for $plans plans (want 4 each)"; fail=1; }
  [ "$errors" = 0 ] || { echo "FAIL: $errors light errors"; fail=1; }
  [ "$frames" -gt 100 ] || { echo "FAIL: only $frames frames in 4 s"; fail=1; }
fi
[ "$fail" = 0 ] && echo "gvsd-gpio: OK"
exit "$fail"
