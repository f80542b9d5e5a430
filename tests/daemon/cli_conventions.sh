#!/usr/bin/env bash
# Command-line conventions of gvs and gvsd: usage errors exit 2 and say
# what is wrong, --version names the version and the commit, numbers are
# checked as numbers first, unknown commands list the known ones, and the
# help explains scenarios and methods.
# usage: cli_conventions.sh GVS_BINARY GVSD_BINARY SOURCE_DIR PROJECT_VERSION
set -euo pipefail
gvs=$1
gvsd=$2
src=$3
version=$4
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# expect CODE PATTERN CMD...: runs CMD, checks its exit code and that its
# output (stdout and stderr) matches the extended regex PATTERN.
expect() {
  local code=$1 pattern=$2; shift 2
  local out rc=0
  out=$("$@" 2>&1) || rc=$?
  [[ $rc -eq $code ]] || fail "'$*' exited $rc, expected $code: $out"
  grep -Eq -- "$pattern" <<<"$out" || fail "'$*' does not say /$pattern/: $out"
}

# 1. --version on both tools: the project version and the configured commit.
commit="not built from a git checkout"
if git -C "$src" rev-parse --short=12 HEAD >/dev/null 2>&1; then
  commit="git $(git -C "$src" rev-parse --short=12 HEAD)"
fi
for tool in "$gvs" "$gvsd"; do
  name=$(basename "$tool")
  out=$("$tool" --version)
  [[ "$out" == "$name $version ($commit)" ]] || fail "$name --version: '$out', expected '$name $version ($commit)'"
done

# 2. Usage errors exit 2 on both tools; --help exits 0.
expect 2 "--bogus" "$gvs" sim --scenario sine --out "$work/x" --bogus
expect 2 "--bogus" "$gvsd" --bogus
expect 2 "run-for" "$gvsd" --run-for -1
expect 0 "Usage: gvs sim" "$gvs" sim --help
expect 0 "Usage: gvsd" "$gvsd" --help

# 3. Numbers: "not a number" first; zero and negative durations and seeds refused.
expect 2 "'abc' is not a number" "$gvs" sim --scenario sine --out "$work/x" --seconds abc
expect 2 "'abc' is not a number" "$gvsd" --run-for abc
expect 2 "0 is not above 0" "$gvsd" --run-for 0
expect 2 "0 is not above 0" "$gvs" sim --scenario sine --out "$work/x" --seconds 0
expect 2 "-2 is not above 0" "$gvs" sim --scenario sine --out "$work/x" --seconds -2
expect 2 "'-3' is not a seed" "$gvs" sim --scenario sine --out "$work/x" --seed -3
expect 2 "'1e400' is not a number" "$gvs" sim --scenario sine --out "$work/x" --fps 1e400
expect 2 "'12.5' is not a whole number" "$gvs" sim --scenario sine --out "$work/x" --width 12.5
expect 2 "'abc' is not a number" "$gvs" record --out "$work/x" --seconds abc
expect 2 "0 is not above 0" "$gvs" monitor - --seconds 0
[[ ! -e "$work/x" ]] || fail "a refused command created its output"

# 4. Unknown or missing commands: named, with the commands to choose from.
main_help=$("$gvs" --help)
commands=$(sed -n '/^Subcommands:/,/^$/p' <<<"$main_help" | awk 'NR > 1 && NF { print $1 }')  # the list ends at a blank line (a footer follows)
[[ $(wc -w <<<"$commands") -ge 7 ]] || fail "gvs --help lists no subcommands: $commands"
for cmd in "" foo; do
  out=$("$gvs" $cmd 2>&1) && fail "'gvs $cmd' succeeded"
  rc=$("$gvs" $cmd >/dev/null 2>&1; echo $?) || true
  [[ $rc -eq 2 ]] || fail "'gvs $cmd' exited $rc, expected 2"
  [[ -z $cmd ]] || grep -q "unknown command 'foo'" <<<"$out" || fail "'gvs foo' does not name it: $out"
  for c in $commands; do grep -q "\b$c\b" <<<"$out" || fail "'gvs $cmd' does not list $c: $out"; done
done
expect 2 "unknown command 'bar'.*scale, height, yaw" "$gvs" calibrate bar

# 5. Help: every scenario explained, every method listed (the lists are the tool's own).
sim_help=$("$gvs" sim --help)
replay_help=$("$gvs" replay --help)
scenarios=$(sed -n 's/.*--scenario TEXT:{\([^}]*\)}.*/\1/p' <<<"$sim_help" | tr , ' ')
[[ -n "$scenarios" ]] || fail "gvs sim --help does not list the scenarios"
for s in $scenarios; do
  grep -Eq "^ +$s: [a-z0-9].{20,}" <<<"$sim_help" || fail "gvs sim --help does not explain scenario $s"
done
methods=$({ "$gvs" replay "$work" --out "$work/e.csv" --method nope 2>&1 || true; } | sed -n 's/.*choose one of: //p' | tr -d ,)
[[ $(wc -w <<<"$methods") -ge 2 ]] || fail "no method list in the refusal of --method nope"
for m in $methods; do
  grep -q -- "--method.*\b$m\b" <<<"$replay_help" || fail "gvs replay --help does not list method $m"
done
echo "OK conventions"
