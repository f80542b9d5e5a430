#!/usr/bin/env bash
# The manual pages the build writes from the programs' --help
# (cmake/gvs_manpage.py): gvs.1 and gvsd.1 exist with their .gz, gvs.1 has
# every subcommand (and sub-subcommand) `gvs --help` lists and every option
# their --help lists, gvsd.1 every gvsd option, and man (or groff) renders
# both without a warning.
# usage: man_pages.sh MAN_DIR GVS_BINARY GVSD_BINARY
set -euo pipefail
man_dir=$1
gvs=$2
gvsd=$3
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

render() {  # render PAGE: the page as text, warnings on standard error
  if command -v man >/dev/null; then
    MANWIDTH=100 man --warnings -l "$1"
  else
    groff -man -Tutf8 -ww "$1"
  fi
}
subcommands() {  # subcommands HELP_COMMAND...: the names under "Subcommands:"
  "$@" --help | awk '/^Subcommands:/ {s=1; next} /^$/ {s=0} s && /^  [a-z]/ {print $1}'
}
options() {  # options HELP_COMMAND...: every --long option the help lists
  "$@" --help | grep -oE '^  (-[a-z],)?--[a-z-]+' | sed 's/^ *\(-[a-z],\)\{0,1\}//' | sort -u
}

for program in gvs gvsd; do
  page=$man_dir/$program.1
  [[ -s $page ]] || fail "$page was not written"
  [[ $(gzip -dc "$page.gz") == "$(cat "$page")" ]] || fail "$page.gz is not $page"
  render "$page" > "$work/$program.txt" 2> "$work/$program.err"
  [[ ! -s $work/$program.err ]] || fail "$program.1 renders with warnings: $(cat "$work/$program.err")"
  grep -q "^NAME" "$work/$program.txt" && grep -q "^SYNOPSIS" "$work/$program.txt" || fail "$program.1 lacks NAME or SYNOPSIS"
  grep -q "^EXIT STATUS" "$work/$program.txt" || fail "$program.1 lacks EXIT STATUS (the --help footer)"
  grep -q "/usr/share/doc/gvs/" "$work/$program.txt" || fail "$program.1 does not point to the packaged docs"
done

# Text as one line per page, so a wrapped line does not hide a name.
tr -s ' \n' '  ' < "$work/gvs.txt" > "$work/gvs.flat"
tr -s ' \n' '  ' < "$work/gvsd.txt" > "$work/gvsd.flat"
commands=$(subcommands "$gvs")
[[ $(wc -w <<<"$commands") -ge 5 ]] || fail "gvs --help lists only: $commands"
checked=0
for c in $commands; do
  grep -qF " gvs $c " "$work/gvs.flat" || fail "gvs.1 does not mention 'gvs $c'"
  for o in $(options "$gvs" "$c"); do
    grep -qF -- "$o" "$work/gvs.flat" || fail "gvs.1 lacks 'gvs $c $o'"; checked=$((checked + 1))
  done
  for s in $(subcommands "$gvs" "$c"); do
    grep -qF "Usage: gvs $c $s " "$work/gvs.flat" || fail "gvs.1 lacks 'gvs $c $s'"
    for o in $(options "$gvs" "$c" "$s"); do
      grep -qF -- "$o" "$work/gvs.flat" || fail "gvs.1 lacks 'gvs $c $s $o'"; checked=$((checked + 1))
    done
  done
done
for o in $(options "$gvsd"); do
  grep -qF -- "$o" "$work/gvsd.flat" || fail "gvsd.1 lacks '$o'"; checked=$((checked + 1))
done
echo "man pages: $(wc -w <<<"$commands") gvs commands and $checked options found"
echo "OK man pages"
