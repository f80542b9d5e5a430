#!/usr/bin/env bash
# gvs replay --timing: the per-frame costs, then every estimator stage alone
# on frame pairs of the run, with a CPU time each (the laser dots' stage on a
# run that shows them, not with --no-lasers): the same stages, by name, as
# the benchmark's BM_Stage table (eval::estimator_stages(), one table for
# both) when the benchmark program is given.
# usage: cli_replay_timing.sh GVS_BINARY [GVS_ESTIMATOR_BENCH]
set -euo pipefail
gvs=$1
bench=${2:-}
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$gvs" sim --scenario sine --seconds 0.5 --seed 2 --exposure double-pulse --lasers --out "$work/run" > /dev/null
"$gvs" replay "$work/run" --out "$work/run.csv" --timing > "$work/replay.txt"
cat "$work/replay.txt"
grep -Eq '^timing per frame: decode PNG [0-9.]+ ms, estimator [0-9.]+ ms' "$work/replay.txt" \
  || fail "no per-frame timing line"
grep -q '^stages alone, CPU per call on 8 frame pairs of the run' "$work/replay.txt" || fail "no stage table"
# name, a time > 0, a description
stages=$(awk '/^stages alone/ {on = 1; next} on && /^  [a-z_]+ +[0-9.]+ ms  / {print $1, $2}' "$work/replay.txt")
[[ $(echo "$stages" | wc -l) -ge 10 ]] || fail "fewer than 10 stages timed: $stages"
while read -r name ms; do
  awk -v t="$ms" 'BEGIN {exit !(t > 0)}' || fail "stage $name took $ms ms"
done <<< "$stages"
replay_names=$(echo "$stages" | awk '{print $1}' | sort)
grep -qx laser_dots <<< "$replay_names" || fail "no laser_dots stage on a run with laser dots"
"$gvs" replay "$work/run" --out "$work/nolasers.csv" --timing --no-lasers > "$work/nolasers.txt"
grep -q '^stages alone' "$work/nolasers.txt" || fail "no stage table with --no-lasers"
! grep -q '^  laser_dots ' "$work/nolasers.txt" || fail "a laser_dots stage timed with --no-lasers"
[[ $(echo "$replay_names" | uniq -d) == "" ]] || fail "a stage listed twice"

if [[ -n $bench ]]; then
  # The benchmark's stages less its two yardsticks (FFTW r2c, cv::dft).
  bench_names=$("$bench" --benchmark_list_tests --benchmark_filter='^BM_Stage/' | cut -d/ -f2 |
    grep -v -e '^fftw_r2c_measure$' -e '^cv_dft_forward$' | sort)
  [[ $bench_names == "$replay_names" ]] \
    || fail "replay's stages differ from the benchmark's: $(diff <(echo "$bench_names") <(echo "$replay_names"))"
  echo "the benchmark's BM_Stage names the same $(echo "$bench_names" | wc -l) stages"
else
  echo "SKIPPED: the comparison with the benchmark's stage names (benchmarks not built: GVS_BUILD_BENCHMARKS=OFF)"
fi
echo "OK replay timing"
