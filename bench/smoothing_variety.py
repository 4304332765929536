#!/usr/bin/env python3
# Times generated CAM polylines through one or more softmc binaries in jerk mode, for changes to the
# smoothing of CAM polylines (docs/planner.md, "Smoothing CAM polylines"): the four bench programs
# and 3D_Chips.ngc are five paths; these are sixteen more of the kinds that smoothing meets.
#
#   /usr/bin/python3 bench/smoothing_variety.py [--out DIR] [--count 16] BIN [BIN2 ...]
#
# Each program is seeded by its number (the same files every time): a surface raster over a wall
# (seed % 4 == 0), a spiral whose legs are now and then 0.05x or 8x the step (1), a contour of long and
# short legs (2), noisy circles of R2, R5, R12 (3); P 0.01-0.2 mm, steps 0.1-1 mm, 3 or 4 decimals,
# F1200-F6000. The machine is the LinuxCNC comparison's (100 mm/s, 1 000 mm/s^2 per axis) with
# --jerk (10 000 mm/s^3), a window of 200 blocks. Prints each binary's cycle time and path deviation
# per program, and the ratio of each binary's time to the first's. A run that is not `ok` or leaves
# its P prints FAIL.
import argparse
import json
import math
import os
import random
import subprocess
import sys


def program(seed):
    r = random.Random(seed)
    kind = seed % 4
    tol = r.choice([0.01, 0.02, 0.05, 0.1, 0.2])
    dec = r.choice([3, 4])
    step = r.choice([0.1, 0.25, 0.5, 1.0])
    out = [f"G21 G90 G64 P{tol}", "G0 X0 Y0 Z5", f"G1 Z0 F{r.choice([1200, 3000, 6000])}"]

    def g1(x, y, z):
        return f"G1 X{x:.{dec}f} Y{y:.{dec}f} Z{z:.{dec}f}"

    if kind == 0:  # a surface raster over a wall
        height, width = r.uniform(1, 5), r.uniform(0.1, 0.5)
        for row in range(6):
            y = row * 2.0
            xs = [i * step for i in range(int(40 / step) + 1)]
            if row % 2:
                xs = xs[::-1]
            for x in xs:
                out.append(g1(x, y, -height / (1 + math.exp(-(x - 20) / width)) + 0.3 * math.sin(x * 0.5 + y)))
    elif kind == 1:  # a spiral with uneven legs
        t, rad = 0.0, 10.0
        while t < 6 * math.pi:
            t += step * r.choice([1, 1, 1, 0.05, 8]) / rad
            rad = 10 + 2 * math.sin(3 * t)
            out.append(g1(rad * math.cos(t), rad * math.sin(t), 0))
    elif kind == 2:  # a contour of long and short legs
        x = y = 0.0
        for k in range(400):
            ang = k * 0.02 + 0.3 * math.sin(k * 0.1)
            leg = step * (r.choice([1, 1, 1, 1, 20]) if k % 37 else 30)
            x += leg * math.cos(ang)
            y += leg * math.sin(ang)
            out.append(g1(x, y, -0.5 * math.sin(k * 0.05)))
    else:  # noisy circles
        for rad in (2, 5, 12):
            n = max(8, int(2 * math.pi * rad / step))
            for i in range(n + 1):
                a = 2 * math.pi * i / n
                out.append(g1(rad * math.cos(a) + r.uniform(-1, 1) * 10 ** -dec, rad * math.sin(a), 0))
    out += ["G0 Z5", "M2"]
    return tol, "\n".join(out) + "\n"


def run(binary, path, jerk):
    args = [binary, "run", "--json", path, "--set", "planner.lookahead=200"]
    for ax in "xyz":
        for key, val in (("max_vel_mm_s", 100), ("max_acc_mm_s2", 1000), ("max_jerk_mm_s3", jerk),
                         ("min_mm", -1000), ("max_mm", 1000), ("ferror_limit_mm", 1000)):
            args += ["--set", f"axes.{ax}.{key}={val}"]
    res = subprocess.run(args, capture_output=True, text=True)
    try:
        d = json.loads(res.stdout)
    except json.JSONDecodeError:
        return None
    return d


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binaries", nargs="+")
    ap.add_argument("--out", default="/tmp/smoothing_variety")
    ap.add_argument("--count", type=int, default=16)
    ap.add_argument("--jerk", type=float, default=10000.0)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    ratios = [[] for _ in a.binaries]
    print("program  P mm  " + "  ".join(f"bin{i + 1} s / dev mm / ratio" for i in range(len(a.binaries))))
    for seed in range(1, a.count + 1):
        tol, text = program(seed)
        path = os.path.join(a.out, f"c{seed}.ngc")
        with open(path, "w") as f:
            f.write(text)
        cells, first = [], None
        for i, b in enumerate(a.binaries):
            d = run(b, path, a.jerk)
            if not d or d.get("result", "ok") != "ok" or d.get("max_path_deviation_mm", 0) > tol * (1 + 1e-9):
                cells.append("FAIL")
                continue
            t = d["cycle_time_s"]
            first = first or t
            ratios[i].append(t / first)
            cells.append(f"{t:8.3f} / {d['max_path_deviation_mm']:.4f} / {t / first:.3f}")
        print(f"c{seed:<7} {tol:<5} " + "  ".join(cells))
    for i, rs in enumerate(ratios[1:], start=1):
        if rs:
            rs = sorted(rs)
            print(f"bin{i + 1}/bin1: min {rs[0]:.3f}  median {rs[len(rs) // 2]:.3f}  max {rs[-1]:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
