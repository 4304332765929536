#!/usr/bin/env python3
"""A lower bound on the time ANY planner needs to run a G-code program within a tolerance P under
per-axis speed and acceleration limits (no jerk limit: the trapezoid case of issue 4's goal).

    /usr/bin/python3 bench/time_lower_bound.py --build build PROGRAM.ngc [...] [--vel 100]
        [--acc 1000] [--tol 0.05] [--compare SECONDS ...]
    /usr/bin/python3 bench/time_lower_bound.py --build build --check --fuzz N [--seed S]

The program's geometry comes from `softmc moves` (lines and arcs; the canonical moves, so the
G-code is read by softmc's interpreter). What is assumed of a planner, and nothing else
(docs/planner.md, "A lower bound on any planner's time"):
  1. Each axis keeps |v| <= vel and |a| <= acc. The path speed keeps to the feed of the program
     point it is matched to in 2 (override 100 %), or to a neighbouring move's higher feed on the
     half of a move next to it (a blend's). --ignore-feed drops this part: the bound then rests
     on the axes' limits alone.
  2. The path follows the program in order within P: each programmed point p is passed within P
     at a time t(p) that does not decrease along the program (a Frechet matching), and between
     two such times the path stays within P of the program between the two points.
  3. The machine is at rest exactly on the programmed point at M codes (but M62/M63/M67), M3/M5,
     M6, dwells, pauses, M66 and the program's end, as LinuxCNC and softmc both are.
Then, between any two gates (programmed points) g < h, the time T = t(h) - t(g):
  - the path length |p_h - p_g| - 2P at the feed;
  - each axis covering |dx| - 2P, entering and leaving no faster than its turning points allow:
    where the program's coordinate reverses by more than 2P the axis must turn (speed 0) within P
    of that coordinate, so at a point d mm short of a turning coordinate ahead, or d mm past one
    behind, |v| <= sqrt(2*acc*(d + 2P)) (turn_room);
  - over two legs g -> j -> h with S = T1 + T2 and rho = T1/S, the mean velocities of the legs
    differ per axis by at most acc*S/2: |rho*p_h - p_j + (1 - rho)*p_g| - 2P <=
    acc*S^2*rho*(1 - rho)/2, the curvature bound (a circle of radius R cannot be run faster than
    about sqrt(acc*R) however the legs are cut).
The gates (every 0.5 mm and at every turning point) and the legs and pairs of legs are chosen by
dynamic programming to make the sum over disjoint intervals largest. Each step is a sound
inequality, so no planner keeping 1-3 is quicker than the figure printed. --check runs programs
whose least time is known in closed form; --fuzz N runs N random programs through softmc, which
keeps 1-3, and fails if the bound is ever above softmc's own time.
"""
import argparse
import json
import math
import random

import numpy as np
import subprocess
import sys

AXES = 'XYZ'
MOTION = {'rapid', 'feed', 'arc'}
# Events at which every planner is at rest on the programmed point (assumption 3). Others (path
# mode, offsets, messages, a T word, an S word, synchronised outputs) are taken as not stopping,
# which only weakens the bound.
STOPS = {'dwell', 'spindle', 'tool_change', 'pause', 'wait_input', 'end'}
SYNCED_M = {62, 63, 67}  # M62/M63/M67 act with the motion after them
STEP = 0.05  # mm between samples of the program (extrema and chords)


def load_moves(binary, program):
    r = subprocess.run([binary, 'moves', program], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"softmc moves {program} failed: {r.stderr.strip()}")
    return [json.loads(line) for line in r.stdout.splitlines() if line.strip()]


def arc_geometry(pos, m):
    """An arc move of `softmc moves` from pos: (end, (ia, ib, ic), (ca, cb), (r0, r1), a0, sweep):
    the plane's two axes in their order and the third, the centre, the start and end radii (a
    spiral's differ), the start angle and the signed sweep (turns included). Also used by
    compare_linuxcnc.py."""
    end = [m['end'].get(a, pos[i]) for i, a in enumerate(AXES)]
    c = m['center']
    ia, ib = {'XY': (0, 1), 'ZX': (2, 0), 'YZ': (1, 2)}[m['plane']]
    ic = 3 - ia - ib
    ca, cb = c[AXES[ia]], c[AXES[ib]]
    r0 = math.hypot(pos[ia] - ca, pos[ib] - cb)
    r1 = math.hypot(end[ia] - ca, end[ib] - cb)
    a0 = math.atan2(pos[ib] - cb, pos[ia] - ca)
    a1 = math.atan2(end[ib] - cb, end[ia] - ca)
    turns = m.get('turns', 1)
    sweep = a1 - a0
    if m['direction'] == 'ccw':
        while sweep <= 1e-12:
            sweep += 2 * math.pi
        sweep += 2 * math.pi * (turns - 1)
    else:
        while sweep >= -1e-12:
            sweep -= 2 * math.pi
        sweep -= 2 * math.pi * (turns - 1)
    return end, (ia, ib, ic), (ca, cb), (r0, r1), a0, sweep


def arc_at(pos, geo, f):
    """The arc's point at fraction f of its sweep (radius and the third axis linear in f)."""
    end, (ia, ib, ic), (ca, cb), (r0, r1), a0, sweep = geo
    ang = a0 + sweep * f
    r = r0 + (r1 - r0) * f
    p = [0.0, 0.0, 0.0]
    p[ia] = ca + r * math.cos(ang)
    p[ib] = cb + r * math.sin(ang)
    p[ic] = pos[ic] + (end[ic] - pos[ic]) * f
    return p


def arc_points(pos, m):
    """Samples of an arc move at most STEP apart: (points after pos, end, sag). sag bounds how far
    the arc passes beyond the chord between two samples (r + 2|dr/dtheta|)*dtheta^2/8 (a spiral's
    radius changes with its angle)."""
    geo = arc_geometry(pos, m)
    end, axes, _, (r0, r1), _, sweep = geo
    length = math.hypot(abs(sweep) * max(r0, r1), end[axes[2]] - pos[axes[2]])
    n = max(2, math.ceil(length / STEP))
    dth = abs(sweep) / n
    sag = (max(r0, r1) + 2 * abs(r1 - r0) / abs(sweep)) * dth * dth / 8 * 1.01
    return [arc_at(pos, geo, k / n) for k in range(1, n + 1)], end, sag


def sections_of(moves, default_tol):
    """Runs of motion between stops: [(points, feeds, tol, sag)]. feeds[k] is the feed (mm/s; inf
    for rapids) of the move that reaches points[k], or of its neighbour where that is higher on the
    half of the move next to it: a blend may cross part of a move at its neighbour's feed (and
    takes at most half of each move, as LinuxCNC's and softmc's do). sag (mm) bounds how far an
    arc's extreme may lie beyond its samples."""
    out, pos, tol = [], [0.0, 0.0, 0.0], default_tol
    pts, move, half, feed_of, sag, sec_tol = [], [], [], [], 0.0, 0.0

    def close():
        nonlocal pts, move, half, feed_of, sag, sec_tol
        if len(pts) > 1:
            last = len(feed_of) - 1
            feeds = [max(feed_of[m], feed_of[m - 1 if h == 0 else min(m + 1, last)]) for m, h in zip(move, half)]
            out.append((pts, feeds, sec_tol, sag))  # the largest P of the section's moves
        pts, move, half, feed_of, sag, sec_tol = [], [], [], [], 0.0, 0.0

    for m in moves:
        t = m['type']
        if t == 'path_mode':
            # A tolerance change needs no stop; a section takes the largest P of its moves.
            tol = (m.get('tolerance_mm') or default_tol) if m.get('mode') == 'blend' else 0.0
            continue
        sec_tol = max(sec_tol, tol)
        if t in ('spline', 'nurbs'):
            sys.exit(f"line {m['line']}: {t} moves are not sampled by this script (lines and arcs only)")
        if t not in MOTION:
            stops = t in STOPS or (t == 'm' and m['number'] not in SYNCED_M) or (
                t in ('digital_output', 'analog_output') and not m.get('synced'))
            if stops:
                close()
            continue
        target = [m['end'].get(a, pos[i]) for i, a in enumerate(AXES)]
        if t != 'arc' and math.dist(pos, target) == 0:
            continue  # no move (and no blend)
        if not pts:
            pts, move, half = [pos[:]], [0], [1]
            feed_of = [0.0]  # the start: no move, no blend
        if t == 'arc':
            new, end, arc_sag = arc_points(pos, m)
            sag = max(sag, arc_sag)
        else:
            end = [m['end'].get(a, pos[i]) for i, a in enumerate(AXES)]
            n = max(1, math.ceil(math.dist(pos, end) / STEP))
            new = [[pos[i] + (end[i] - pos[i]) * k / n for i in range(3)] for k in range(1, n + 1)]
        feed_of.append(m.get('feed_mm_s', math.inf) if t != 'rapid' else math.inf)
        pts += new
        move += [len(feed_of) - 1] * len(new)
        half += [0 if 2 * (k + 1) <= len(new) else 1 for k in range(len(new))]
        pos = end
    close()
    return out


def zigzag(xs, h):
    """Indices of the program coordinate's turning points: alternate maxima and minima, each
    confirmed by a reversal of more than h, with the first and last samples (at rest) as ends.
    Between two turning points the values lie between theirs (the last stretch, to the end at
    rest, may come back by up to h)."""
    n = len(xs)
    ext, hi, lo, d = [0], 0, 0, 0
    for k in range(1, n):
        x = xs[k]
        if d == 0:
            hi = k if x > xs[hi] else hi
            lo = k if x < xs[lo] else lo
            if xs[hi] - x > h:
                if hi != 0:
                    ext.append(hi)
                d, lo = -1, k
            elif x - xs[lo] > h:
                if lo != 0:
                    ext.append(lo)
                d, hi = 1, k
        elif d == 1:
            if x > xs[hi]:
                hi = k
            elif xs[hi] - x > h:
                ext.append(hi)
                d, lo = -1, k
        else:
            if x < xs[lo]:
                lo = k
            elif x - xs[lo] > h:
                ext.append(lo)
                d, hi = 1, k
    last = hi if d == 1 else lo if d == -1 else n - 1
    if last not in (ext[-1], n - 1):
        ext.append(last)
    if ext[-1] != n - 1:
        ext.append(n - 1)
    return ext


def turn_room(xs, p, sag=0.0):
    """(rooms, the turning points' indices). For each sample k, r_k (mm) with |v(t_k)|^2 <= 2*acc*r_k for this axis whatever the planner
    (the module's docstring). In a stretch rising from turning point a to turning point b, a speed
    along the stretch is bounded by the room to the highest point ahead (the path turns near b:
    the program falls by more than 2P after it, or b is the end at rest) and from the lowest point
    behind (it turned near a, or a is the start at rest); a speed against the stretch by the room
    to the lowest point ahead before the path must rise again (within 2P of b's height: the lowest
    point up to the next turning point beyond b, or to the end). Each room gets 2P: x(t_k) is
    within P of x_k and the real turning points within P of the program's. Falling stretches
    alike, mirrored."""
    n = len(xs)
    ext = zigzag(xs, 2 * p)
    room = [math.inf] * n
    for s in range(len(ext) - 1):
        a, b = ext[s], ext[s + 1]
        sign = 1.0 if xs[b] >= xs[a] else -1.0
        y = [sign * xs[k] for k in range(a, b + 1)]
        # The lowest point from b to the turning point after it (or the end): the path turns there
        # at the latest (a confirmed rise, the end at rest, or the last candidate, after which the
        # program stays above it up to the end at rest).
        c = ext[s + 2] if s + 2 < len(ext) else n - 1
        beyond = min(sign * xs[k] for k in range(b, c + 1))
        m = len(y)
        sufmin, sufmax = [0.0] * m, [0.0] * m
        lo, hi = math.inf, -math.inf
        for k in range(m - 1, -1, -1):
            lo, hi = min(lo, y[k]), max(hi, y[k])
            sufmin[k], sufmax[k] = lo, hi
        premin = math.inf
        for k, yk in enumerate(y):
            premin = min(premin, yk)
            along = min(sufmax[k] - yk, yk - premin)
            against = yk - (sufmin[k] if y[-1] - yk > 2 * p else min(sufmin[k], beyond))
            i = a + k
            room[i] = min(room[i], max(along, against) + 2 * p + sag)
    return room, ext


def t_1d(dist, b0, b1, vmax, acc):
    """Least time to travel dist >= 0 (arrays), entering no faster than b0 and leaving no faster
    than b1, with |v| <= vmax and |a| <= acc."""
    dist = np.maximum(dist, 0.0)
    v0 = np.minimum(np.minimum(b0, vmax), np.sqrt(b1 * b1 + 2 * acc * dist))
    v1 = np.minimum(np.minimum(b1, vmax), np.sqrt(v0 * v0 + 2 * acc * dist))
    peak2 = acc * dist + (v0 * v0 + v1 * v1) / 2
    vm = np.minimum(np.sqrt(peak2), vmax)
    ramps = (2 * vm * vm - v0 * v0 - v1 * v1) / (2 * acc)
    with np.errstate(divide='ignore', invalid='ignore'):
        cruise = np.where(vm > 0, np.maximum(dist - ramps, 0.0) / vm, 0.0)
    return np.where(dist > 0, (2 * vm - v0 - v1) / acc + cruise, 0.0)


RHO_CELLS = 24  # cells of the split T1/(T1+T2) in a pair of legs (each bounded from below on its cell)


def section_bound(pts, feeds, tol, sag, vel, acc, window_mm, gate_mm):
    """The least time of one section (from rest on its first point to rest on its last)."""
    n = len(pts)
    rooms, turns = [], set()
    for i in range(3):
        room, ext = turn_room([q[i] for q in pts], tol, sag)
        rooms.append(room)
        turns.update(ext)
    # Gates: every gate_mm of path, every axis's turning points, the ends.
    s, gates, last = 0.0, [0], 0.0
    arc = [0.0] * n
    for k in range(1, n):
        s += math.dist(pts[k - 1], pts[k])
        arc[k] = s
        if k == n - 1 or s - last >= gate_mm or k in turns:
            gates.append(k)
            last = s
    g = np.array(gates)
    m = len(g)
    pos = np.array([pts[k] for k in gates])                 # m x 3
    at = np.array([arc[k] for k in gates])
    margin = np.where((g == 0) | (g == n - 1), 0.0, tol)    # the ends: exactly on the point
    room = np.array([[rooms[i][k] for i in range(3)] for k in gates])
    speed = np.where(margin[:, None] > 0, np.minimum(vel, np.sqrt(2 * acc * room)), 0.0)
    feeds = np.asarray(feeds)
    # The highest feed on each gate's stretch from the gate before it (its own samples included),
    # and a sparse table of its range maxima for cap().
    fstretch = np.array([feeds[gates[j - 1]:gates[j] + 1].max() if j > 0 else feeds[0] for j in range(m)])
    table = [fstretch]
    while 2 ** len(table) <= m:
        h = 2 ** (len(table) - 1)
        prev = table[-1]
        table.append(np.maximum(prev[:-h], prev[h:]))

    def cap(a, b):
        """The feed bounding the path between gates a < b (arrays): the highest on their samples."""
        lo, hi = a + 1, b
        lvl = np.floor(np.log2(hi - lo + 1)).astype(int)
        out = np.empty(len(lo))
        for L in np.unique(lvl):
            sel = lvl == L
            t = table[L]
            out[sel] = np.maximum(t[lo[sel]], t[hi[sel] - 2 ** L + 1])
        return np.maximum(out, feeds[g[a]])

    def legs(i, k, fcap):
        """Least time between gates i and k (arrays), fcap the feed that bounds the path there."""
        mg = margin[i] + margin[k]
        d = pos[k] - pos[i]
        vcap = np.minimum(vel, fcap)
        t = np.where(np.isfinite(fcap), np.maximum(np.linalg.norm(d, axis=1) - mg, 0.0) / fcap, 0.0)
        for ax in range(3):
            t = np.maximum(t, t_1d(np.abs(d[:, ax]) - mg, speed[i, ax], speed[k, ax], vcap, acc))
        return t

    # Pairs of legs i -> j -> k: the path's mean velocities over the two legs (displacement/time)
    # differ per axis by at most acc*(T1 + T2)/2. With S = T1 + T2 and rho = T1/S:
    #   |rho*r_k - r_j + (1 - rho)*r_i| <= acc * S^2 * rho*(1 - rho) / 2, each r within P of its
    # point: S >= sqrt(2*(|rho*p_k - p_j + (1 - rho)*p_i| - 2P) / (acc*rho*(1 - rho))), and
    # S >= T1/rho, T2/(1 - rho) from each leg's own bound. The least S over rho is bounded below
    # cell by cell (each term's least value on the cell).
    edges = np.linspace(0.0, 1.0, RHO_CELLS + 1)
    ra, rb = edges[:-1], edges[1:]
    rmid = np.clip(0.5, ra, rb)
    rr_max = rmid * (1 - rmid)  # largest rho*(1 - rho) on each cell

    def pairs(i, j, k, t1, t2):
        pi, pj, pk = pos[i][:, None, :], pos[j][:, None, :], pos[k][:, None, :]
        # |rho*p_k - p_j + (1 - rho)*p_i| is |linear in rho|: its least value on a cell is at an
        # end, or 0 where it changes sign within.
        va = ra[None, :, None] * pk - pj + (1 - ra[None, :, None]) * pi
        vb = rb[None, :, None] * pk - pj + (1 - rb[None, :, None]) * pi
        lo = np.where(va * vb <= 0, 0.0, np.minimum(np.abs(va), np.abs(vb)))
        # Each r within its margin of the point: rho*m_k + m_j + (1 - rho)*m_i <= m_j + max(m_i, m_k).
        mg = (margin[j] + np.maximum(margin[i], margin[k]))[:, None, None]
        need = np.maximum(lo - mg, 0.0).max(axis=2)          # worst axis, pairs x cells
        with np.errstate(divide='ignore'):
            s_acc = np.sqrt(2 * need / (acc * rr_max[None, :]))
            s_t1 = np.where(rb[None, :] > 0, t1[:, None] / rb[None, :], np.inf)
            s_t2 = np.where(ra[None, :] < 1, t2[:, None] / (1 - ra[None, :]), np.inf)
        return np.maximum(np.maximum(s_acc, s_t1), s_t2).min(axis=1)

    best = np.zeros(m)
    for k in range(1, m):
        lo_i = max(0, int(np.searchsorted(at, at[k] - window_mm, side='left')))
        lo_i = min(lo_i, k - 1)
        i = np.arange(lo_i, k)
        kk = np.full_like(i, k)
        top = best[i] + legs(i, kk, cap(i, kk))
        # Pairs with their middle gate halfway along the path.
        sel = i[i <= k - 2]
        if len(sel):
            j = np.searchsorted(at, (at[sel] + at[k]) / 2)
            j = np.clip(j, sel + 1, k - 1)
            kk = np.full_like(sel, k)
            t1 = legs(sel, j, cap(sel, j))
            t2 = legs(j, kk, cap(j, kk))
            s2 = pairs(sel, j, kk, t1, t2)
            top[:len(sel)] = np.maximum(top[:len(sel)], best[sel] + s2)
        best[k] = top.max()
    return float(best[-1])


def program_bound(binary, program, vel=100.0, acc=1000.0, tol=0.05, window_mm=20.0, gate_mm=0.5, ignore_feed=False):
    """(the least time of the whole program, its number of sections); tol is P where the program
    sets none (G61: a hair, 1e-9 mm)."""
    secs = sections_of(load_moves(binary, program), tol)
    total = 0.0
    for p, f, t, sg in secs:
        feeds = [math.inf] * len(f) if ignore_feed else f
        total += section_bound(p, feeds, t if t > 0 else 1e-9, sg, vel, acc, window_mm, gate_mm)
    return total, len(secs)


# Programs whose least time is known in closed form (every axis 100 mm/s, 1000 mm/s^2): the bound
# must not exceed it, and should come close.
CHECKS = [
    ('line at the axis speed', 'G0 X0 Y0 Z0\nG1 X100 F6000\nM2\n', 100 / 100 + 100 / 1000),
    ('line at half the axis speed', 'G0 X0 Y0 Z0\nG1 X100 F3000\nM2\n', 100 / 50 + 50 / 1000),
    ('diagonal rapid', 'G0 X0 Y0 Z0\nG0 X100 Y100\nM2\n', 100 / 100 + 100 / 1000),
    ('rectangle, exact stop', 'G61\nG0 X0 Y0 Z0\nG1 X40 F6000\nG1 Y20\nG1 X0\nG1 Y0\nM2\n',
     2 * (40 / 100 + 0.1) + 2 * (20 / 100 + 0.1)),
    ('short zigzag, exact stop', 'G61\nG0 X0 Y0 Z0\nG1 X2 F6000\nG1 X0\nG1 X2\nM2\n', 3 * 2 * (2 / 1000) ** 0.5),
]


def self_check(binary):
    import tempfile
    import os
    bad = 0
    with tempfile.TemporaryDirectory() as d:
        for name, text, best in CHECKS:
            path = os.path.join(d, 'check.ngc')
            with open(path, 'w') as f:
                f.write(text)
            got = program_bound(binary, path)[0]
            ok = got <= best + 1e-9 and got >= 0.95 * best
            bad += not ok
            print(f"{'ok ' if ok else 'BAD'} {name:<28} bound {got:.4f} s, least time {best:.4f} s ({got / best:.3f})")
    return bad


def random_program(rnd):
    """A short random program: lines in any direction and length, arcs, rapids, feeds, a P."""
    x = [rnd.uniform(-50, 50) for _ in range(3)]
    tol = rnd.choice((0.005, 0.01, 0.05, 0.1, 0.5, 0))
    mode = f"G64 P{tol}" if tol > 0 else "G61"
    out = [f"G21 G90 G17 {mode}", "G0 X%.4f Y%.4f Z%.4f" % tuple(x)]
    for _ in range(rnd.randint(3, 40)):
        k = rnd.random()
        f = rnd.choice((600, 1500, 3000, 6000, 9000))
        if k < 0.1:  # a CAM polyline: short chords of a wavy curve
            h, amp, wl = rnd.uniform(0, 2 * math.pi), rnd.uniform(0.1, 5), rnd.uniform(2, 30)
            step = rnd.choice((0.1, 0.25, 0.5))
            for q in range(rnd.randint(20, 200)):
                h += rnd.uniform(-0.3, 0.3) * step
                x = [x[0] + step * math.cos(h), x[1] + step * math.sin(h),
                     x[2] + step * amp / wl * math.cos(2 * math.pi * q * step / wl)]
                out.append("G1 X%.4f Y%.4f Z%.4f F%d" % (x[0], x[1], x[2], f))
        elif k < 0.55:
            d = rnd.choice((0.05, 0.3, 1, 5, 30)) * rnd.uniform(0.2, 1)
            u = [rnd.gauss(0, 1) for _ in range(3)]
            if rnd.random() < 0.6:
                u[2] = 0
            if rnd.random() < 0.3:  # along one axis
                u = [0, 0, 0]
                u[rnd.randrange(3)] = rnd.choice((-1, 1))
            nrm = math.sqrt(sum(c * c for c in u)) or 1
            x = [x[i] + d * u[i] / nrm for i in range(3)]
            out.append("G1 X%.4f Y%.4f Z%.4f F%d" % (x[0], x[1], x[2], f))
        elif k < 0.8:
            r = rnd.choice((0.5, 2, 10, 40)) * rnd.uniform(0.3, 1)
            a0 = rnd.uniform(0, 2 * math.pi)
            cx, cy = x[0] - r * math.cos(a0), x[1] - r * math.sin(a0)
            a1 = a0 + rnd.uniform(0.2, 6)
            ex, ey = cx + r * math.cos(a1), cy + r * math.sin(a1)
            out.append("G%d X%.4f Y%.4f I%.4f J%.4f F%d" % (rnd.choice((2, 3)), ex, ey, cx - x[0], cy - x[1], f))
            x = [ex, ey, x[2]]
        elif k < 0.9:
            x = [x[i] + rnd.uniform(-20, 20) for i in range(3)]
            out.append("G0 X%.4f Y%.4f Z%.4f" % tuple(x))
        else:
            out.append(rnd.choice(("M3", "M5", "G4 P0.1")))
    out.append("M2")
    return "\n".join(out) + "\n"


def fuzz(binary, n, seed):
    """softmc keeps every assumption (P, the limits, the feed, stops), so its time on the same
    machine can never be below the bound: any program where it is shows a fault in one of them."""
    import tempfile
    import os
    rnd = random.Random(seed)
    lim = []
    for ax in 'xyz':
        lim += ['--set', f'axes.{ax}.max_vel_mm_s=100', '--set', f'axes.{ax}.max_acc_mm_s2=1000',
                '--set', f'axes.{ax}.max_jerk_mm_s3=0', '--set', f'axes.{ax}.min_mm=-1000',
                '--set', f'axes.{ax}.max_mm=1000', '--set', f'axes.{ax}.ferror_limit_mm=1000']
    bad, worst = 0, 0.0
    with tempfile.TemporaryDirectory() as d:
        for k in range(n):
            path = os.path.join(d, f'f{k}.ngc')
            with open(path, 'w') as f:
                f.write(random_program(rnd))
            r = subprocess.run([binary, 'run', path, '--json'] + lim, capture_output=True, text=True)
            if r.returncode != 0:
                continue  # a program the machine refuses (travel, arcs): nothing to compare
            run = json.loads(r.stdout)
            got = program_bound(binary, path)[0]
            ratio = got / run['cycle_time_s'] if run['cycle_time_s'] > 0 else 0
            worst = max(worst, ratio)
            if got > run['cycle_time_s'] + 2 * run['period_s']:
                bad += 1
                keep = f'time_lower_bound_fuzz_{seed}_{k}.ngc'
                with open(keep, 'w') as f, open(path) as g:
                    f.write(g.read())
                print(f"BAD {keep}: bound {got:.4f} s above softmc's {run['cycle_time_s']:.4f} s")
    print(f"{n} programs, {bad} with the bound above softmc's time; the closest bound/time {worst:.3f}")
    return bad


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('programs', nargs='*')
    ap.add_argument('--build', default='build', help='build directory holding apps/softmc/softmc')
    ap.add_argument('--vel', type=float, default=100.0, help='every axis, mm/s')
    ap.add_argument('--acc', type=float, default=1000.0, help='every axis, mm/s^2')
    ap.add_argument('--tol', type=float, default=0.05, help='P where the program sets none, mm')
    ap.add_argument('--window', type=float, default=20.0, help='longest leg between gates, mm of path')
    ap.add_argument('--gate', type=float, default=0.5, help='gate spacing, mm of path')
    ap.add_argument('--compare', nargs='*', type=float, default=[],
                    help="a time per program (s), e.g. LinuxCNC's: prints bound/time")
    ap.add_argument('--ignore-feed', action='store_true',
                    help='assume nothing of the path speed (the bound from the axis limits and P alone)')
    ap.add_argument('--check', action='store_true', help='check the bound on programs whose least time is known')
    ap.add_argument('--fuzz', type=int, default=0, metavar='N',
                    help="N random programs: the bound must stay below softmc's own time on each")
    ap.add_argument('--seed', type=int, default=1)
    a = ap.parse_args()
    binary = f"{a.build}/apps/softmc/softmc"
    if a.check or a.fuzz:
        bad = self_check(binary) if a.check else 0
        bad += fuzz(binary, a.fuzz, a.seed) if a.fuzz else 0
        sys.exit(1 if bad else 0)
    for k, prog in enumerate(a.programs):
        total, nsec = program_bound(binary, prog, a.vel, a.acc, a.tol, a.window, a.gate, a.ignore_feed)
        line = f"{prog.split('/')[-1]:<24} sections {nsec:3d}  lower bound {total:8.3f} s"
        if k < len(a.compare):
            line += f"  against {a.compare[k]:.3f} s: {total / a.compare[k]:.3f}"
        print(line, flush=True)


if __name__ == '__main__':
    main()
