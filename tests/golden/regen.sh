#!/bin/bash
# Regenerates the golden canonical moves (*.rs274) of the conformance programs in iso/ with
# LinuxCNC 2.9's standalone interpreter `rs274` (Debian package linuxcnc-uspace). Only this script
# needs LinuxCNC; the golden test reads the files it writes.
#
#   tests/golden/regen.sh            # every iso/*.ngc
#   tests/golden/regen.sh iso/x.ngc  # one program
#
# Kept: the canonical calls the test compares (STRAIGHT_TRAVERSE, STRAIGHT_FEED, ARC_FEED) and the
# ones that give them meaning (SELECT_PLANE, USE_LENGTH_UNITS, USE_TOOL_LENGTH_OFFSET), without rs274's
# running numbers. rs274 alone reads its tool table (tool.tbl) in inches; machine.toml gives softmc
# the same tools in mm (tool_mm.tbl).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
command -v rs274 >/dev/null || { echo "regen.sh: rs274 not found (apt-get install linuxcnc-uspace)" >&2; exit 1; }
progs=()
for a in "$@"; do progs+=("$(realpath "$a")"); done
[ ${#progs[@]} -eq 0 ] && progs=("$here"/iso/*.ngc)
for p in "${progs[@]}"; do
  out="${p%.ngc}.rs274"
  raw="$(cd "$here" && rs274 -g -t tool.tbl "$p" </dev/null 2>&1)"
  if grep -qiE '^(.*error|.*differs|.*not )' <<<"$raw" && ! grep -q 'STRAIGHT\|ARC_FEED' <<<"$raw"; then
    echo "regen.sh: rs274 refused $p:" >&2; echo "$raw" | tail -5 >&2; exit 1
  fi
  { echo "# rs274 (LinuxCNC $(dpkg-query -W -f='${Version}' linuxcnc-uspace 2>/dev/null || echo '?')) canonical output of $(basename "$p"); regenerate with tests/golden/regen.sh"
    grep -E 'STRAIGHT_TRAVERSE\(|STRAIGHT_FEED\(|ARC_FEED\(|SELECT_PLANE\(|USE_LENGTH_UNITS\(|USE_TOOL_LENGTH_OFFSET\(' <<<"$raw" | sed -E 's/^ *[0-9]+ N[.0-9]+ +//'
  } >"$out"
  echo "$out: $(grep -cE 'STRAIGHT|ARC_FEED' "$out") moves"
done
