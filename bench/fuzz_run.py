#!/usr/bin/python3
# Random G-code programs through `softmc run --json` on random machines: every axis within its speed,
# acceleration and (where it has one) jerk limit, the path deviation within the largest tolerance
# the program sets (G64 P; G61 alone: 1e-6 mm), and the run ends "ok" (or is rejected only for a
# path outside the travel). Each failing program is saved with the --set arguments (and stimulus)
# that reproduce it.
#
#   bench/fuzz_run.py [--build DIR] [--out DIR] [--seed N] [--minutes M]
#
# Programs: CAM-like polylines (1 µm … 20 mm steps, gently turning runs), arcs, helices, G5 cubics,
# rapids, M codes (M62/M63/M67 too since 2026-12-05: the path runs through them) and dwells, feed changes, G61 / G64 P. Machines: per axis 50–500 mm/s, 200–10 000
# mm/s², jerk 0 (none) or 10³–10⁶ mm/s³, often the same on every axis and sometimes on some axes only;
# look-ahead windows of 4–2 000 blocks; periods of 0.25–2 ms; smoothing off, on, or at 5°/45°; half
# of the runs with a PLC stimulus (feed holds, overrides 0–200 %, axis enables dropping and coming
# back). The failures it found at stop 23 are in docs/planner.md ("Not yet", "Found at stop 23").
#
# --floor: the same programs, stimuli and machines, except that the period is 0.1, 0.25 or 0.5 ms
# and each jerk-limited axis's jerk j is drawn so that one cycle of it, j·dt³, lies log-uniformly in
# [floor, 2e-8] mm (the floor is motion::kMinJerkStep_mm, read from src/motion/limits.hpp: 2e-9; the
# default mode never goes below 1.6e-8). --floor-min / --floor-max change that range (the floor was 2e-10 mm before this fuzzer
# measured it with --floor-min 2e-10: docs/planner.md, "Tiny jerk per cycle"). Each program's smallest j·dt³ is in its
# failN.txt, and every program (failed or not) is one JSON line in runs.jsonl: its j·dt³, period,
# each axis's jerk and measured jerk over its limit, and the failure, if any (docs/planner.md,
# "Tiny jerk per cycle").
import argparse
import json
import math
import os
import random
import re
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def jerk_floor():
    # The least j·dt³ the configuration accepts, from its one definition.
    src = open(os.path.join(HERE, "..", "src", "motion", "limits.hpp")).read()
    return float(re.search(r"kMinJerkStep_mm\s*=\s*([0-9.eE+-]+);", src).group(1))


ap = argparse.ArgumentParser()
ap.add_argument("--build", default=os.path.join(HERE, "..", "build"))
ap.add_argument("--out", default="fuzz_run_out")
ap.add_argument("--seed", type=int, default=1)
ap.add_argument("--minutes", type=float, default=10)
ap.add_argument("--floor", action="store_true", help="machines near the jerk floor (see above)")
ap.add_argument("--floor-min", type=float, default=jerk_floor(), help="least j·dt³ in mm of --floor")
ap.add_argument("--floor-max", type=float, default=2e-8, help="largest j·dt³ in mm of --floor")
args = ap.parse_args()
BIN = os.path.join(args.build, "apps", "softmc", "softmc")
until = time.time() + 60 * args.minutes
rng = random.Random(args.seed)
out = args.out
os.makedirs(out, exist_ok=True)
runs = open(f"{out}/runs.jsonl", "a")
n_prog = n_fail = 0

def prog_text(r):
    P = r.choice([0.005, 0.01, 0.05, 0.1, 0.5])
    lines = ["G21 G90 G17", f"G64 P{P}" if r.random() < 0.85 else "G61", "G0 X50 Y50 Z10"]
    x, y, z = 50.0, 50.0, 10.0
    feed = r.choice([300, 1200, 3000, 6000, 12000])
    lines.append(f"F{feed}")
    for k in range(r.randint(3, 120)):
        t = r.random()
        if t < 0.45:  # short lines, CAM-like
            step = r.choice([0.001, 0.01, 0.05, 0.2, 1.0, 5.0, 20.0])
            h = r.uniform(0, 2 * math.pi)
            nx, ny = x + step * math.cos(h), y + step * math.sin(h)
            nz = z + (r.uniform(-1, 1) * step * 0.3 if r.random() < 0.3 else 0)
            nx, ny, nz = min(max(nx, 1), 99), min(max(ny, 1), 99), min(max(nz, 1), 19)
            lines.append(f"G1 X{nx:.4f} Y{ny:.4f} Z{nz:.4f}")
            x, y, z = nx, ny, nz
        elif t < 0.6:  # a polyline run turning gently
            h = r.uniform(0, 2 * math.pi); dh = r.uniform(-0.3, 0.3); L = r.choice([0.05, 0.25, 0.5])
            for _ in range(r.randint(5, 60)):
                h += dh * r.uniform(0.5, 1.5)
                nx, ny = min(max(x + L * math.cos(h), 1), 99), min(max(y + L * math.sin(h), 1), 99)
                lines.append(f"G1 X{nx:.4f} Y{ny:.4f}")
                x, y = nx, ny
        elif t < 0.8:  # arc
            R = r.choice([0.3, 1, 3, 10])
            a0 = r.uniform(0, 2 * math.pi)
            cx, cy = x - R * math.cos(a0), y - R * math.sin(a0)
            sweep = r.uniform(0.1, 2 * math.pi) * (1 if r.random() < 0.5 else -1)
            a1 = a0 + sweep
            nx, ny = cx + R * math.cos(a1), cy + R * math.sin(a1)
            if not (1 < nx < 99 and 1 < ny < 99 and 1 < cx - R and cx + R < 99 and 1 < cy - R and cy + R < 99):
                continue
            lines.append(f"{'G3' if sweep > 0 else 'G2'} X{nx:.4f} Y{ny:.4f} I{cx - x:.4f} J{cy - y:.4f}")
            x, y = nx, ny
        elif t < 0.88:  # cubic spline
            nx, ny = min(max(x + r.uniform(-5, 5), 1), 99), min(max(y + r.uniform(-5, 5), 1), 99)
            lines.append(f"G5 I{r.uniform(-2,2):.3f} J{r.uniform(-2,2):.3f} P{r.uniform(-2,2):.3f} Q{r.uniform(-2,2):.3f} X{nx:.4f} Y{ny:.4f}")
            x, y = nx, ny
        elif t < 0.905:
            nx, ny, nz = r.uniform(1, 99), r.uniform(1, 99), r.uniform(1, 19)
            lines.append(f"G0 X{nx:.4f} Y{ny:.4f} Z{nz:.4f}")
            x, y, z = nx, ny, nz
        elif t < 0.915:  # a helix turn in XY climbing in Z
            R = r.choice([0.5, 2, 5]); a0 = r.uniform(0, 2 * math.pi)
            cx, cy = x - R * math.cos(a0), y - R * math.sin(a0)
            if 1 < cx - R and cx + R < 99 and 1 < cy - R and cy + R < 99:
                nz = min(max(z + r.uniform(-2, 2), 1), 19)
                sw = r.uniform(0.5, 6); a1 = a0 + sw
                nx, ny = cx + R * math.cos(a1), cy + R * math.sin(a1)
                lines.append(f"G3 X{nx:.4f} Y{ny:.4f} Z{nz:.4f} I{cx - x:.4f} J{cy - y:.4f}")
                x, y, z = nx, ny, nz
        elif t < 0.93:
            lines.append(r.choice(["M3", "M5", "G4 P0.01", "M8", "M9", "M62 P0", "M63 P0", "M67 E0 Q50"]))
        elif t < 0.97:
            lines.append(f"F{r.choice([60, 300, 1200, 3000, 6000, 12000])}")
        else:
            lines.append(r.choice(["G61", f"G64 P{r.choice([0.005, 0.01, 0.05, 0.1])}"]))
    lines.append("M2")
    return "\n".join(lines) + "\n"
while time.time() < until:
    n_prog += 1
    text = prog_text(rng)
    path = f"{out}/p.ngc"
    open(path, "w").write(text)
    sets = []
    lim = {}
    if args.floor:  # the period first: the jerk is drawn for it
        period = rng.choice([0.0001, 0.00025, 0.0005])
        lo, hi = math.log(args.floor_min), math.log(args.floor_max)
    for a in "xyz":
        v = rng.choice([50, 100, 200, 500]); acc = rng.choice([200, 1000, 3000, 10000])
        j = rng.choice([0, 1000, 10000, 100000, 1000000]) if a != "z" or rng.random() < 0.8 else 0
        if args.floor and j > 0:
            j = float(f"{math.exp(rng.uniform(lo, hi)) / period**3:.6g}")
            j = max(j, float(f"{args.floor_min / period**3 * (1 + 1e-5):.6g}"))  # not refused by rounding
        if rng.random() < 0.7 and a != "x": j = lim["x"][2]
        lim[a] = (v, acc, j)
        sets += ["--set", f"axes.{a}.max_vel_mm_s={v}", "--set", f"axes.{a}.max_acc_mm_s2={acc}",
                 "--set", f"axes.{a}.max_jerk_mm_s3={j}", "--set", f"axes.{a}.min_mm=0", "--set", f"axes.{a}.max_mm=100",
                 "--set", f"axes.{a}.ferror_limit_mm=1000"]
    la = rng.choice([200, 2000, 16, 4])
    sets += ["--set", f"planner.lookahead={la}"]
    dt = 0.001  # the built-in machine's period
    if args.floor: dt = period
    elif rng.random() < 0.3: dt = rng.choice([0.00025, 0.0005, 0.002])
    if dt != 0.001: sets += ["--set", f"period_s={dt}"]
    jdt3 = [lim[a][2] * dt**3 for a in "xyz" if lim[a][2] > 0]
    min_jdt3 = min(jdt3) if jdt3 else None
    if rng.random() < 0.2: sets += ["--set", f"planner.smoothing_turn_deg={rng.choice([0, 5, 45])}"]
    stim = []
    if rng.random() < 0.5:
        t = 0.0
        hold = False; en = True
        for _ in range(rng.randint(1, 8)):
            t += rng.uniform(0.005, 1.5)
            k = rng.random()
            if k < 0.4: hold = not hold; stim.append(f"{t:.4f} feed_hold {int(hold)}")
            elif k < 0.7: stim.append(f"{t:.4f} feed_override_permille {rng.choice([0, 100, 500, 1000, 1200, 2000])}")
            elif k < 0.85: en = not en; stim.append(f"{t:.4f} axis_enable[{rng.choice('XYZ')}] {int(en)}")
            else: stim.append(f"{t:.4f} feed_override_permille 1000")
        t += 0.5
        stim += [f"{t:.4f} feed_hold 0", f"{t:.4f} feed_override_permille 1000"] + [f"{t:.4f} axis_enable[{a}] 1" for a in "XYZ"]
        open(f"{out}/p.stim", "w").write("\n".join(stim) + "\n")
        sets += ["--stimulus", f"{out}/p.stim"]
    def save(why):
        # failN.ngc, failN.stim (the stimulus, when there is one) and failN.txt: what failed, then
        # the arguments after `softmc run failN.ngc --json` that reproduce it.
        global n_fail
        n_fail += 1
        open(f"{out}/fail{n_fail}.ngc", "w").write(text)
        if stim: open(f"{out}/fail{n_fail}.stim", "w").write("\n".join(stim) + "\n")
        saved = " ".join(sets).replace(f"{out}/p.stim", f"{out}/fail{n_fail}.stim")
        floor = f"smallest j*dt^3 {min_jdt3:.4g} mm (period {dt:g} s)" if min_jdt3 else f"no jerk limit (period {dt:g} s)"
        open(f"{out}/fail{n_fail}.txt", "w").write("; ".join(why) + "\n" + saved + "\n" + floor + "\n")
    def record(why, d):
        # One line per program in runs.jsonl: where the failures are against j·dt³ (and how close the
        # others came: each axis's measured jerk over its limit).
        rec = {"n": n_prog, "period_s": dt, "min_jdt3_mm": min_jdt3, "j": {a: lim[a][2] for a in "xyz"},
               "stim": bool(stim), "wall_s": round(time.time() - t_start, 3), "fail": n_fail if why else None,
               "why": why}
        if d is not None and d.get("result") == "ok":
            rec["j_ratio"] = {a: d["axes"][a]["max_jerk_mm_s3"] / lim[a][2] for a in "xyz" if lim[a][2] > 0}
            rec["cycle_time_s"] = d.get("cycle_time_s")
        elif d is not None:
            rec["result"] = d.get("result")
        runs.write(json.dumps(rec) + "\n"); runs.flush()
    t_start = time.time()
    try:
        r = subprocess.run([BIN, "run", path, "--json"] + sets, capture_output=True, text=True, timeout=600)
    except subprocess.TimeoutExpired:
        save(["TIMEOUT (600 s of wall time)"])
        record(["TIMEOUT (600 s of wall time)"], None)
        continue
    why = []
    try:
        d = json.loads(r.stdout)
    except Exception:
        why.append(f"no json rc={r.returncode} {r.stderr[:300]}")
        d = None
    if d is not None:
        if d.get("result") == "rejected" and all("leaves the travel" in x["message"] for x in d["diagnostics"]): pass
        elif d.get("result") != "ok": why.append("result " + str(d.get("result"))[:200])
        else:
            # The tolerance contract (docs/planner.md "What the tolerance P bounds"): every setpoint
            # within P of the program; the largest P the program sets bounds them all.
            p_max = max([float(m) for m in re.findall(r"G64 P([0-9.]+)", text)] + [0.0])
            dev = d.get("max_path_deviation_mm", 0.0)
            # Where (the summary's *_at: time and line), so the failure is found in the program.
            def at(w): return f" (line {w['line']} at {w['t_s']:.4f} s)" if w else ""
            if dev > p_max * (1 + 1e-6) + 1e-6:
                why.append(f"deviation {dev:.6g} mm > P {p_max:g}{at(d.get('max_path_deviation_at'))}")
            for a in "xyz":
                v, acc, j = lim[a]; m = d["axes"][a]
                if m["max_vel_mm_s"] > v * (1 + 1e-6) + 1e-6: why.append(f"{a} v {m['max_vel_mm_s']/v:.6f}{at(m.get('max_vel_at'))}")
                if m["max_acc_mm_s2"] > acc * (1 + 1e-6) + 1e-3: why.append(f"{a} a {m['max_acc_mm_s2']/acc:.6f}{at(m.get('max_acc_at'))}")
                if j > 0 and m["max_jerk_mm_s3"] > j * (1 + 1e-4) + 2:
                    why.append(f"{a} j {m['max_jerk_mm_s3']/j:.6f}{at(m.get('max_jerk_at'))}")
    if why:
        save(why)
    record(why, d)
    if n_prog % 20 == 0:
        print(f"{n_prog} programs, {n_fail} failures", flush=True)
print(f"done: {n_prog} programs, {n_fail} failures (saved in {out})", flush=True)
