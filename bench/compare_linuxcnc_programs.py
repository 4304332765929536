#!/usr/bin/env python3
# Writes the realistic benchmark programs of examples/gcode/bench/ (the LinuxCNC comparison's own set).
#
#   python3 bench/compare_linuxcnc_programs.py [OUT_DIR]      (default: examples/gcode/bench)
#
# Deterministic: the same files every time. Each program is what a CAM post-processor would emit for
# its job (3-decimal coordinates, one move per line), sized to run 10-40 s at 100 mm/s.
import math
import os
import sys


def f3(v):
    s = f"{v:.3f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def xyz(**kw):
    return " ".join(f"{k.upper()}{f3(v)}" for k, v in kw.items())


def surfacing():
    # 3D finishing raster of a ball-nose over a wavy surface: tiny G1 steps (0.25 mm along X) whose
    # direction changes by a few degrees each, the 3D_Chips kind of program, boustrophedon in Y.
    out = ["%", "(3D surfacing raster: 0.25 mm steps over a wavy surface, 20 passes 2 mm apart, F6000)",
           "G21 G90 G17 G94", "G0 Z5", "G0 X0 Y0", "G1 Z-2 F6000"]
    def z(x, y):
        return -3 + 2.0 * math.sin(x / 7.0) * math.cos(y / 11.0) + 0.6 * math.sin(x / 2.3 + y / 5.0)
    n = 240
    for row in range(20):
        y = 2.0 * row
        xs = [60.0 * i / n for i in range(n + 1)]
        if row % 2:
            xs.reverse()
        out.append(f"G1 {xyz(x=xs[0], y=y, z=z(xs[0], y))}")
        for x in xs[1:]:
            out.append(f"G1 {xyz(x=x, z=z(x, y))}")
    out += ["G0 Z5", "M30", "%"]
    return out


def pocket():
    # Rounded-rectangle pocket 60 x 40, corner radius 6, cleared by inward offsets 2.5 mm apart at
    # two depths: straight sides joined by tangent G3 quarter arcs, step-over moves as short lines.
    out = ["%", "(Pocket 60 x 40 x 2 deep, R6 corners, offsets 2.5 mm, 2 depths, F6000)",
           "G21 G90 G17 G94", "G0 Z5", "G0 X40 Y25"]
    cx, cy, w, h, r0 = 40.0, 25.0, 60.0, 40.0, 6.0
    for depth in (-1.0, -2.0):
        out.append(f"G1 Z{f3(depth)} F6000")
        for k in range(9, -1, -1):  # innermost first, out to the wall
            off = 2.5 * k
            hw, hh = w / 2 - off, h / 2 - off
            r = max(0.5, r0 - off)
            if hw <= r or hh <= r:
                continue
            x0, x1, y0, y1 = cx - hw, cx + hw, cy - hh, cy + hh
            out.append(f"G1 {xyz(x=x0 + r, y=y0)}")
            out.append(f"G1 {xyz(x=x1 - r, y=y0)}")
            out.append(f"G3 {xyz(x=x1, y=y0 + r)} I0 J{f3(r)}")
            out.append(f"G1 {xyz(x=x1, y=y1 - r)}")
            out.append(f"G3 {xyz(x=x1 - r, y=y1)} I{f3(-r)} J0")
            out.append(f"G1 {xyz(x=x0 + r, y=y1)}")
            out.append(f"G3 {xyz(x=x0, y=y1 - r)} I0 J{f3(-r)}")
            out.append(f"G1 {xyz(x=x0, y=y0 + r)}")
            out.append(f"G3 {xyz(x=x0 + r, y=y0)} I{f3(r)} J0")
        out.append(f"G1 {xyz(x=cx, y=cy)}")
    out += ["G0 Z5", "M30", "%"]
    return out


def engraving():
    # V-bit engraving of twelve glyph-like figures: rose curves and stars as 0.4 mm chords with sharp
    # corners, each one plunged, drawn and lifted, the way a font post-processor writes text.
    out = ["%", "(Engraving: 12 figures, 0.4 mm chords, sharp star corners, plunge 0.3 mm, F4800)",
           "G21 G90 G17 G94", "G0 Z3"]
    for g in range(12):
        ox, oy = 15.0 + 25.0 * (g % 4), 15.0 + 25.0 * (g // 4)
        pts = []
        if g % 3 == 2:  # star: 5..9 points, straight edges
            m = 5 + g % 5
            for i in range(2 * m + 1):
                rr = 10.0 if i % 2 == 0 else 4.0
                a = math.pi * i / m
                pts.append((ox + rr * math.cos(a), oy + rr * math.sin(a)))
        else:  # rose r = 10 cos(k t), sampled by chord ≈ 0.4 mm
            k = 2 + g % 4
            n = int(2 * math.pi * 10 * k / 0.4)
            span = math.pi if k % 2 else 2 * math.pi
            for i in range(n + 1):
                t = span * i / n
                rr = 10.0 * math.cos(k * t)
                pts.append((ox + rr * math.cos(t), oy + rr * math.sin(t)))
        out.append(f"G0 {xyz(x=pts[0][0], y=pts[0][1])}")
        out.append("G1 Z-0.3 F4800")
        for p in pts[1:]:
            out.append(f"G1 {xyz(x=p[0], y=p[1])}")
        out.append("G0 Z3")
    out += ["M30", "%"]
    return out


def plasma():
    # Plasma profiles: a flange outline of lines and non-tangent arcs (notches), slots of two tangent
    # arcs and two lines, and bolt holes as full circles with lead-in arcs; the torch is switched on
    # and off around every cut (M3/M5), which stops the motion there as on a real table.
    out = ["%", "(Plasma: flange outline with arc notches, 2 slots, 8 bolt holes with lead-ins, F6000)",
           "G21 G90 G17 G94", "G0 Z0"]
    cx, cy, ro = 60.0, 60.0, 50.0
    # bolt holes: a line from the centre, a quarter-arc lead-in tangent to the hole, the full circle
    for i in range(8):
        a = 2 * math.pi * i / 8
        hx, hy, hr = cx + 35 * math.cos(a), cy + 35 * math.sin(a), 5.0
        out.append(f"G0 {xyz(x=hx, y=hy)}")
        out.append("M3")
        out.append(f"G1 {xyz(x=hx + hr / 2, y=hy - hr / 2)} F6000")
        out.append(f"G3 {xyz(x=hx + hr, y=hy)} I0 J{f3(hr / 2)}")
        out.append(f"G3 {xyz(x=hx + hr, y=hy)} I{f3(-hr)} J0")
        out.append("M5")
    # slots: two lines joined by half circles (tangent)
    for sx, sy in ((cx - 12, cy - 3), (cx - 12, cy + 9)):
        out.append(f"G0 {xyz(x=sx, y=sy)}")
        out.append("M3")
        out.append(f"G1 {xyz(x=sx + 24, y=sy)} F6000")
        out.append(f"G3 {xyz(x=sx + 24, y=sy + 6)} I0 J3")
        out.append(f"G1 {xyz(x=sx, y=sy + 6)}")
        out.append(f"G3 {xyz(x=sx, y=sy)} I0 J-3")
        out.append("M5")
    # outline: 12 outer arcs of the flange joined by arc notches that meet them at corners
    n = 12
    start = None
    cut = []
    for i in range(n):
        a0 = 2 * math.pi * i / n + 0.08
        a1 = 2 * math.pi * (i + 1) / n - 0.08
        p0 = (cx + ro * math.cos(a0), cy + ro * math.sin(a0))
        p1 = (cx + ro * math.cos(a1), cy + ro * math.sin(a1))
        if start is None:
            start = p0
        cut.append(f"G3 {xyz(x=p1[0], y=p1[1])} I{f3(cx - p0[0])} J{f3(cy - p0[1])}")
        # notch: a small clockwise arc into the next lobe, centred on the outline
        a2 = 2 * math.pi * (i + 1) / n + 0.08
        q = (cx + ro * math.cos(a2), cy + ro * math.sin(a2))
        mid = (cx + ro * math.cos((a1 + a2) / 2), cy + ro * math.sin((a1 + a2) / 2))
        cut.append(f"G2 {xyz(x=q[0], y=q[1])} I{f3(mid[0] - p1[0])} J{f3(mid[1] - p1[1])}")
    out.append(f"G0 {xyz(x=start[0] + 5, y=start[1])}")
    out.append("M3")
    out.append(f"G1 {xyz(x=start[0], y=start[1])} F6000")
    out += cut
    out.append("M5")
    out += ["G0 X0 Y0", "M30", "%"]
    return out


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "examples", "gcode", "bench")
    os.makedirs(out_dir, exist_ok=True)
    for name, fn in (("surfacing", surfacing), ("pocket", pocket), ("engraving", engraving), ("plasma", plasma)):
        with open(os.path.join(out_dir, name + ".ngc"), "w") as f:
            f.write("\n".join(fn()) + "\n")


if __name__ == "__main__":
    main()
