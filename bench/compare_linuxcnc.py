#!/usr/bin/python3
# softmc's planner against LinuxCNC 2.9's on the same programs and the same simulated machine.
#
#   bench/compare_linuxcnc.py [PROGRAM.ngc ...] [--build DIR] [--vel 100] [--acc 1000] [--jerk 10000]
#                             [--tol 0.05] [--work DIR] [--reuse] [--softmc-set KEY=VALUE ...]
#
# For each program: one LinuxCNC run (shared/tools/linuxcnc/lcnc_trace.sh beside the checkout, or
# $LCNC_TRACE; a headless
# linuxcnc-uspace on a simulated XYZ trivkins machine; it takes the program's real time), and two
# softmc runs in virtual time on the same axes (v, a per axis, travel ±1000 mm, the same G64 P):
# jerk limiting off (trapezoids, as LinuxCNC plans) and on (max_jerk_mm_s3 = --jerk on every axis).
# Printed per program: execution times, their ratio, limit violations and path deviation, and the
# least time any planner keeping these limits within P could take (bench/time_lower_bound.py).
#
# Measured the same way on both traces (positions every 1 ms):
#   violations  samples whose per-axis speed (first difference), acceleration (second difference)
#               or, on the jerk run, jerk (third difference) exceeds the axis limit by more than
#               1e-6 relative, counted per kind;
#               (plus the noise the CSV's rounding puts into the differences: 9 digits);
#   deviation   largest distance of a sample from the programmed path (lines and arcs of the
#               program as `softmc moves` reads it, arcs as polylines with chord error < 1e-4 mm),
#               and the largest distance of a programmed exact-stop point (before an M code or
#               dwell, the program end) from the trace's closest sample.
# Needs /usr/bin/python3 with numpy, linuxcnc-uspace, and a built softmc (--build, default build).
import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import time_lower_bound  # noqa: E402
ROOT = os.path.normpath(os.path.join(HERE, ".."))
LCNC = os.environ.get("LCNC_TRACE", os.path.join(ROOT, "..", "shared", "tools", "linuxcnc", "lcnc_trace.sh"))
AXES = "xyz"


def softmc_sets(vel, acc, jerk, tol, lookahead):
    s = []
    for a in AXES:
        s += ["--set", f"axes.{a}.max_vel_mm_s={vel}", "--set", f"axes.{a}.max_acc_mm_s2={acc}",
              "--set", f"axes.{a}.max_jerk_mm_s3={jerk}", "--set", f"axes.{a}.min_mm=-1000",
              "--set", f"axes.{a}.max_mm=1000", "--set", f"axes.{a}.ferror_limit_mm=1000"]
    s += ["--set", f"planner.tolerance_mm={tol}", "--set", f"planner.lookahead={lookahead}"]
    return s


def run_softmc(exe, prog, out_csv, sets):
    r = subprocess.run([exe, "run", prog, "--json", "--trace", out_csv] + sets, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"softmc failed on {prog}: {r.stdout}{r.stderr}")
    info = json.loads(r.stdout)
    if info.get("result") != "ok":
        raise RuntimeError(f"softmc: {prog}: {info.get('result')}")
    d = np.genfromtxt(out_csv, delimiter=",", names=True)
    pos = np.column_stack([d[f"{a}_cmd_mm"] for a in AXES])
    return info["cycle_time_s"], pos


def run_lcnc(prog, out_csv, vel, acc, tol, reuse):
    if not (reuse and os.path.exists(out_csv)):
        r = subprocess.run([LCNC, prog, out_csv, "--vel", str(vel), "--acc", str(acc), "--g64", str(tol)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"lcnc_trace failed on {prog} ({r.returncode}): {r.stdout[-2000:]}{r.stderr[-2000:]}")
    d = np.genfromtxt(out_csv, delimiter=",", names=True)
    pos = np.column_stack([d[a] for a in AXES])
    dt = float(d["t_s"][1] - d["t_s"][0])
    return (len(pos) - 1) * dt, pos


def program_path(exe, prog):
    """The programmed path as a polyline (N×3) plus the rest points (exact stops), from `softmc moves`."""
    r = subprocess.run([exe, "moves", prog], capture_output=True, text=True, check=True)
    cur = np.zeros(3)
    pts = [cur.copy()]
    rests = []
    for line in r.stdout.splitlines():
        m = json.loads(line)
        t = m["type"]
        if t in ("feed", "rapid", "arc"):
            end = np.array([m["end"].get(a.upper(), cur[i]) for i, a in enumerate(AXES)])
            if t == "arc":
                pts += arc_points(cur, end, m)
            pts.append(end)
            cur = end
        elif t in ("m", "dwell", "end"):
            rests.append(cur.copy())
    rests.append(cur.copy())
    return np.array(pts), np.array(rests)


def arc_points(p0, p1, m):
    """The arc's inner points, chord error under 1e-4 mm (geometry: time_lower_bound.arc_geometry)."""
    geo = time_lower_bound.arc_geometry(list(p0), m)
    r = max(geo[3])
    n = max(8, int(abs(geo[5]) / (2 * math.acos(max(-1.0, 1 - 1e-4 / max(r, 1e-9))))) + 1)
    return [np.array(time_lower_bound.arc_at(list(p0), geo, k / n)) for k in range(1, n)]


def path_deviation(path, pos, near_mm=1.0):
    """Largest distance of the trace samples from the polyline `path`. Exact: each chunk of samples is
    compared with every segment whose bounding box comes within near_mm of the chunk's (all of them
    when a sample is farther than that)."""
    a, b = path[:-1], path[1:]
    d = b - a
    l2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    seg_lo, seg_hi = np.minimum(a, b), np.maximum(a, b)
    worst = 0.0

    def nearest(p, idx):
        A, D, L2 = a[idx], d[idx], l2[idx]
        rel = p[:, None, :] - A[None, :, :]
        t = np.clip(np.einsum("ijk,jk->ij", rel, D) / L2, 0, 1)
        return np.min(np.linalg.norm(rel - t[:, :, None] * D[None, :, :], axis=2), axis=1)

    for s in range(0, len(pos), 64):
        p = pos[s:s + 64]
        lo, hi = p.min(axis=0) - near_mm, p.max(axis=0) + near_mm
        idx = np.where(np.all((seg_hi >= lo) & (seg_lo <= hi), axis=1))[0]
        best = nearest(p, idx) if len(idx) else np.full(len(p), np.inf)
        far = best > near_mm
        if np.any(far):
            best[far] = nearest(p[far], np.arange(len(a)))
        worst = max(worst, float(best.max()))
    return worst


def rest_deviation(rests, pos):
    """Largest distance of a programmed exact-stop point (before an M code or dwell, the program's end)
    from the closest sample of the trace: the path must pass through every one of them."""
    worst = 0.0
    for r in rests:
        worst = max(worst, float(np.min(np.linalg.norm(pos - r, axis=1))))
    return worst


def quantum(csv_path):
    """Half the last printed digit of the trace's positions: softmc writes 9 significant digits,
    LinuxCNC's harness 9 decimals. Finite differences of rounded positions carry ±2q/dt (speed) and
    ±4q/dt² (acceleration) of noise, which the violation count allows for."""
    with open(csv_path) as f:
        f.readline()
        row = f.readline().strip().split(",")
    decimals = max(len(x.split(".")[1]) if "." in x else 0 for x in row[1:])
    if decimals >= 9:
        return 0.5e-9
    return None  # significant digits: per sample, from the magnitude


def violations(pos, dt, vel, acc, q, jerk=0.0):
    if q is None:  # 9 significant digits
        mag = np.maximum(np.abs(pos), 1e-3)
        qs = 0.5 * 10.0 ** (np.floor(np.log10(mag)) - 8)
    else:
        qs = np.full(pos.shape, q)
    v = np.diff(pos, axis=0) / dt
    a = np.diff(v, axis=0) / dt
    nv_allow = 2 * np.maximum(qs[1:], qs[:-1]) / dt
    na_allow = 4 * np.maximum(np.maximum(qs[2:], qs[1:-1]), qs[:-2]) / dt ** 2
    nv = int(np.sum(np.any(np.abs(v) > vel * (1 + 1e-6) + nv_allow, axis=1)))
    na = int(np.sum(np.any(np.abs(a) > acc * (1 + 1e-6) + na_allow, axis=1)))
    # Jerk (third difference, noise ±8q/dt³) only where a jerk limit was asked for.
    nj = 0
    if jerk > 0:
        j = np.diff(a, axis=0) / dt
        nj_allow = 8 * np.maximum.reduce([qs[3:], qs[2:-1], qs[1:-2], qs[:-3]]) / dt ** 3
        nj = int(np.sum(np.any(np.abs(j) > jerk * (1 + 1e-6) + nj_allow, axis=1)))
    return nv, na, nj, float(np.max(np.abs(v))), float(np.max(np.abs(a)))


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("programs", nargs="*")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--vel", type=float, default=100.0)
    ap.add_argument("--acc", type=float, default=1000.0)
    ap.add_argument("--jerk", type=float, default=10000.0, help="jerk limit of the second softmc run, mm/s^3")
    ap.add_argument("--tol", type=float, default=0.05, help="G64 P for programs that set none, mm")
    ap.add_argument("--lookahead", type=int, default=10000)
    ap.add_argument("--work", default="/tmp/compare_linuxcnc")
    ap.add_argument("--reuse", action="store_true", help="reuse LinuxCNC traces already in --work")
    ap.add_argument("--no-lcnc", action="store_true", help="softmc only")
    ap.add_argument("--softmc-set", action="append", default=[], metavar="KEY=VALUE",
                    help="one more --set for both softmc runs (e.g. planner.smoothing_turn_deg=0)")
    args = ap.parse_args()
    progs = args.programs or [os.path.join(ROOT, "examples/gcode/bench", f)
                              for f in ("surfacing.ngc", "pocket.ngc", "engraving.ngc", "plasma.ngc")]
    exe = os.path.join(args.build, "apps/softmc/softmc")
    os.makedirs(args.work, exist_ok=True)
    dt = 0.001
    rows = []
    for prog in progs:
        name = os.path.splitext(os.path.basename(prog))[0]
        path, rests = program_path(exe, prog)
        res = {"program": name}
        res["bound_s"] = time_lower_bound.program_bound(exe, prog, args.vel, args.acc, args.tol)[0]
        runs = []
        if not args.no_lcnc:
            csv = os.path.join(args.work, name + ".lcnc.csv")
            t, pos = run_lcnc(prog, csv, args.vel, args.acc, args.tol, args.reuse)
            runs.append(("lcnc", t, pos, csv))
        for tag, jerk in (("trap", 0), ("jerk", args.jerk)):
            csv = os.path.join(args.work, f"{name}.softmc_{tag}.csv")
            t, pos = run_softmc(exe, prog, csv, softmc_sets(args.vel, args.acc, jerk, args.tol, args.lookahead) +
                                  [x for kv in args.softmc_set for x in ("--set", kv)])
            runs.append((tag, t, pos, csv))
        for tag, t, pos, csv in runs:
            nv, na, nj, vmax, amax = violations(pos, dt, args.vel, args.acc, quantum(csv),
                                                args.jerk if tag == "jerk" else 0.0)
            res[tag] = {"time_s": t, "v_viol": nv, "a_viol": na, "j_viol": nj, "v_max": vmax, "a_max": amax,
                        "dev_mm": path_deviation(path, pos), "rest_dev_mm": rest_deviation(rests, pos)}
        rows.append(res)
        print(json.dumps(res), file=sys.stderr)

    print(f"\nvel {args.vel} mm/s, acc {args.acc} mm/s^2 per axis; G64 P{args.tol} unless the program sets one; "
          f"softmc jerk run: {args.jerk} mm/s^3")
    hdr = f"{'program':<12} {'LinuxCNC s':>10} {'softmc s':>9} {'ratio':>6} {'bound s':>8} {'bound/L':>7} {'jerk s':>8} " \
          f"{'viol v,a L/s/j':>20} {'jerk viol j':>11} {'dev mm L/s/j':>20} {'end dev mm L/s/j':>23}"
    print(hdr)
    print("-" * len(hdr))
    for r in rows:
        l, s, j = r.get("lcnc"), r["trap"], r["jerk"]
        lt = f"{l['time_s']:.3f}" if l else "-"
        ratio = f"{s['time_s'] / l['time_s']:.3f}" if l else "-"
        bratio = f"{r['bound_s'] / l['time_s']:.3f}" if l else "-"
        viol = "/".join(f"{x['v_viol']},{x['a_viol']}" if x else "-" for x in (l, s, j))
        dev = "/".join(f"{x['dev_mm']:.3f}" if x else "-" for x in (l, s, j))
        rdev = "/".join(f"{x['rest_dev_mm']:.1e}" if x else "-" for x in (l, s, j))
        print(f"{r['program']:<12} {lt:>10} {s['time_s']:>9.3f} {ratio:>6} {r['bound_s']:>8.3f} {bratio:>7} "
              f"{j['time_s']:>8.3f} {viol:>20} "
              f"{j['j_viol']:>11} {dev:>20} {rdev:>23}")
    print("viol v,a: samples over a speed limit, over an acceleration limit; jerk viol: samples of the jerk run "
          "over its jerk limit (third difference); dev: largest distance from the programmed path; "
          "end dev: largest distance of a programmed stop point from the trace (L = LinuxCNC, s = softmc, "
          "j = softmc with jerk limit); bound: the least time of any planner within these axis limits, the "
          "feed and P (bench/time_lower_bound.py, no jerk limit), and its ratio to LinuxCNC's time")


if __name__ == "__main__":
    main()
