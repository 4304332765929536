#!/usr/bin/env python3
"""Writes a large CAM-like G-code program (default 1,000,000 lines) to stdout, deterministically.

What CAM post-processors emit for 2.5D work: a header, then pockets and profiles made of short
G1 segments with 3-4 decimals, tangent G2/G3 arcs with I/J, Z plunges and retracts, F words on
some lines, comments, line numbers on some blocks. Used by gcode_compare.sh (softmc vs rs274).
"""
import math
import random
import sys


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    rnd = random.Random(1)
    out = sys.stdout
    w = out.write
    w("%\n(generated CAM-like program for the interpreter benchmark)\nG21 G90 G17 G91.1\nG0 Z5\nM3\n")
    lines = 5
    x = y = 0.0
    part = 0
    while lines < n - 3:
        part += 1
        cx, cy = rnd.uniform(20, 400), rnd.uniform(20, 300)
        r = rnd.uniform(5, 30)
        a = 0.0
        x, y = cx + r, cy
        w("(part %d)\nG0 X%.4f Y%.4f\nG1 Z-1.5 F300\n" % (part, x, y))
        lines += 3
        for _ in range(rnd.randint(50, 400)):
            if lines >= n - 3:
                break
            k = rnd.random()
            if k < 0.8:  # tiny chord of a curve
                a += rnd.uniform(0.01, 0.08)
                x, y = cx + r * math.cos(a), cy + r * math.sin(a)
                if rnd.random() < 0.05:
                    w("G1 X%.4f Y%.4f F%d\n" % (x, y, rnd.choice((900, 1200, 1500))))
                else:
                    w("X%.4f Y%.4f\n" % (x, y))
            elif k < 0.95:  # arc about the part centre
                a2 = a + rnd.uniform(0.1, 0.6)
                ex, ey = cx + r * math.cos(a2), cy + r * math.sin(a2)
                w("G3 X%.4f Y%.4f I%.4f J%.4f\nG1\n" % (ex, ey, cx - x, cy - y))
                lines += 1
                x, y, a = ex, ey, a2
            else:
                w("N%d G1 Z%.3f\n" % (lines, -1.5 - rnd.random()))
            lines += 1
        w("G0 Z5\n")
        lines += 1
    w("M5\nM30\n%\n")


if __name__ == "__main__":
    main()
