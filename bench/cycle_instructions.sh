#!/bin/bash
# Instructions per interpolation cycle of the jerk-mode benchmarks, counted by callgrind: the same
# count for the same binary whatever else the machine does, so two binaries (or two commits) compare
# on a shared, noisy machine where their timings would not.
#
#   bench/cycle_instructions.sh [BENCH_BINARY ...]      (default: build/bench/softmc_bench)
#
# For each binary and each benchmark: Interpolator::step's inclusive instructions ÷ the fixed cycle
# count the benchmark runs (BM_JerkCycle4Axes and BM_JerkCycleArcs4Axes: 300 000, BM_JerkCycleSmoothed4Axes: 50 000), with the
# largest callees of the cycle. Needs valgrind (Debian package valgrind). Each run takes ~10 s.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
[ $# -gt 0 ] || set -- "$here/../build/bench/softmc_bench"
command -v valgrind >/dev/null || { echo "cycle_instructions: valgrind not found (apt-get install valgrind)" >&2; exit 1; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

for bin in "$@"; do
  [ -x "$bin" ] || { echo "cycle_instructions: no $bin" >&2; exit 1; }
  echo "== $bin"
  for spec in "JerkCycle4Axes/3:300000" "JerkCycleArcs4Axes/3:300000" "JerkCycleSmoothed4Axes/3:50000"; do
    filter="${spec%%:*}"
    cycles="${spec##*:}"
    valgrind --tool=callgrind --callgrind-out-file="$work/cg.out" "$bin" --benchmark_filter="^BM_$filter" \
      >/dev/null 2>&1
    callgrind_annotate --inclusive=yes "$work/cg.out" 2>/dev/null |
      python3 -c '
import re, sys
cycles, name = float(sys.argv[1]), sys.argv[2]
rows = []
for line in sys.stdin:
    m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+\S*?:(.*?)\s*\[", line)
    if m:
        rows.append((int(m.group(1).replace(",", "")), m.group(2)))
def per_cycle(pattern):
    for n, f in rows:
        if pattern in f:
            return n / cycles
    return 0.0
step = per_cycle("Interpolator::step(double)")
print(f"{name:28s} {step:9.0f} instructions per cycle")
for label, pattern in (("certificate", "JerkGuard::certify("), ("setpoint (Segment::frame)", "Segment::frame("),
                       ("position-mode stop", "StopPlan::step("), ("ramp to rest built", "BrakeRamp::build(")):
    print(f"  {label:26s} {per_cycle(pattern):9.0f}")
' "$cycles" "$filter"
  done
done
