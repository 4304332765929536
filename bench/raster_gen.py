#!/usr/bin/env python3
"""Writes the memory measurement's CAM raster (docs/planner.md, stop 31) to stdout, deterministically.

200 rows of 1 000 G1 steps of 0.1 mm zig-zagging in X over 100 mm, 0.5 mm Y steps between them,
G64 P0.02, F6000: 200 206 lines. With `wave`, every step also moves Z on a gentle wave of ±0.5 mm
(3-D surfacing, which jerk mode smooths into a cubic a line).

    bench/raster_gen.py > raster.ngc; bench/raster_gen.py wave > wave.ngc
"""
import math
import sys


def main():
    wave = len(sys.argv) > 1 and sys.argv[1] == "wave"
    w = sys.stdout.write
    w("G21 G90 G17\nG64 P0.02\nG0 X0 Y0 Z1\nG1 Z0 F6000\n")
    y = 0.0
    for row in range(200):
        for k in range(1, 1001):
            x = (k if row % 2 == 0 else 1000 - k) * 0.1
            if wave:
                w("X%.3f Z%.4f\n" % (x, -1.0 + 0.5 * math.sin(x * 0.2) * math.cos(y * 0.2)))
            else:
                w("X%.3f\n" % x)
        y += 0.5
        w("Y%.3f\n" % y)
    w("G0 Z5\nM2\n")


if __name__ == "__main__":
    main()
