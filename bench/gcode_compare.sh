#!/bin/bash
# Interpreter throughput, softmc vs LinuxCNC 2.9 rs274, on the same large CAM-like program, in one
# run: both read the file and write their canonical output to /dev/null.
#
#   bench/gcode_compare.sh [BUILD_DIR] [LINES]      (defaults: build, 1000000)
#
# Needs rs274 (Debian package linuxcnc-uspace) and a built `softmc`. Prints MB/s and lines/s of
# each and the ratio. Best of three runs each, to keep the other load of the machine out.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="${1:-$here/../build}"
n="${2:-1000000}"
softmc="$build/apps/softmc/softmc"
[ -x "$softmc" ] || { echo "gcode_compare: no $softmc (build the softmc target)" >&2; exit 1; }
command -v rs274 >/dev/null || { echo "gcode_compare: rs274 not found (apt-get install linuxcnc-uspace)" >&2; exit 1; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
prog="$work/cam.ngc"
python3 "$here/gcode_gen.py" "$n" >"$prog"
bytes=$(stat -c %s "$prog")
lines=$(wc -l <"$prog")
cp "$here/../tests/golden/tool.tbl" "$work/tool.tbl"

best() {  # best wall time of 3 runs of "$@", seconds
  local b=""
  for _ in 1 2 3; do
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >/dev/null 2>&1 </dev/null || { echo "gcode_compare: failed: $*" >&2; exit 1; }
    t1=$(date +%s.%N)
    b=$(python3 -c "t=$t1-$t0; b='$b'; print(t if b=='' else min(t, float(b)))")
  done
  echo "$b"
}

t_softmc=$(best "$softmc" moves "$prog")
t_rs274=$(cd "$work" && best rs274 -g -t tool.tbl "$prog" /dev/null)
python3 - "$bytes" "$lines" "$t_softmc" "$t_rs274" <<'PY'
import sys
b, n, ts, tr = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
print(f"program: {n} lines, {b/1e6:.1f} MB")
for name, t in (("softmc moves", ts), ("rs274", tr)):
    print(f"{name:13s} {t:8.3f} s  {b/1e6/t:8.1f} MB/s  {n/t/1e6:7.3f} M lines/s")
print(f"softmc is {tr/ts:.1f}x rs274")
PY
