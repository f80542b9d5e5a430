#!/bin/bash
# check_graph.sh LINKS_FILE ARCHITECTURE_MD: the "gvs links" lines of the
# docs' graph block (`gvs_dsp -> gvs::core`) equal the gvs:: libraries each
# target links (LINKS_FILE, written by CMake: `gvs_dsp: gvs::core, opencv_core`).
set -euo pipefail
links=$1 doc=$2
normalise() { tr ', ' '\n\n' | { grep '^gvs::' || true; } | sort -u | paste -sd' ' -; }
fail=0
declare -A want
in_block=0
while IFS= read -r line; do
  [[ $line == '```gvs-links' ]] && { in_block=1; continue; }
  [[ $in_block == 1 && $line == '```' ]] && break
  if [[ $in_block == 1 && $line =~ ^([a-z_]+)\ *-\>\ *(.*)$ ]]; then
    want[${BASH_REMATCH[1]}]=$(echo "${BASH_REMATCH[2]}" | sed 's/(none)//' | normalise)
  fi
done < "$doc"
[[ ${#want[@]} -gt 0 ]] || { echo "FAIL: no \`\`\`gvs-links block in $doc"; exit 1; }
while IFS= read -r line; do
  target=${line%%:*}
  have=$(echo "${line#*:}" | normalise)
  if [[ -z ${want[$target]+x} ]]; then
    echo "FAIL: $target links [$have] but $doc does not list it"; fail=1
  elif [[ ${want[$target]} != "$have" ]]; then
    echo "FAIL: $target links [$have], $doc says [${want[$target]}]"; fail=1
  fi
  unset "want[$target]"
done < "$links"
for t in "${!want[@]}"; do echo "FAIL: $doc lists $t, which is not a target"; fail=1; done
[[ $fail == 0 ]] && echo "OK: $(wc -l < "$links") targets link as docs/architecture.md shows"
exit $fail
