#!/usr/bin/env python3
"""Draws the geostatic-4x4 transfer error field as a PNG (standard library only).

    bench_transfer geostatic err.csv && plot_geostatic_error.py err.csv transfer/geostatic-error.png

Each particle is a square cell of the 64 x 64 particle lattice (the 4 m column, 16 x 16
elements of 4 x 4 Gauss-Legendre particles), coloured by the signed σyy error over ρgH
on a blue-white-red scale saturating at ±2 %; a colour bar is drawn on the right.
"""
import csv
import struct
import sys
import zlib

SCALE = 0.02  # error over ρgH at full colour
CELL = 8      # pixels per particle


def colour(value):
    t = max(-1.0, min(1.0, value / SCALE))
    if t >= 0:  # white -> red
        return (255, int(255 * (1 - t)), int(255 * (1 - t)))
    return (int(255 * (1 + t)), int(255 * (1 + t)), 255)  # white -> blue


def write_png(path, width, height, rows):
    raw = b"".join(b"\x00" + bytes(row) for row in rows)
    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def main():
    points = [(float(r["x"]), float(r["y"]), float(r["error_over_rho_g_h"]))
              for r in csv.DictReader(open(sys.argv[1]))]
    xs = sorted({round(p[0], 9) for p in points})
    ys = sorted({round(p[1], 9) for p in points})
    field = {(xs.index(round(x, 9)), ys.index(round(y, 9))): e for x, y, e in points}
    bar = 40
    width, height = len(xs) * CELL + bar, len(ys) * CELL
    rows = []
    for py in range(height):
        j = len(ys) - 1 - py // CELL  # y up
        row = []
        for px in range(width):
            if px < len(xs) * CELL:
                row.extend(colour(field[(px // CELL, j)]))
            elif px < len(xs) * CELL + 10:
                row.extend((255, 255, 255))
            else:  # colour bar from +SCALE (top) to -SCALE (bottom)
                row.extend(colour(SCALE * (1 - 2 * py / (height - 1))))
        rows.append(row)
    write_png(sys.argv[2], width, height, rows)
    worst = max(abs(p[2]) for p in points)
    print(f"wrote {sys.argv[2]}: max |error| {worst:.4f} of rho g H, colour scale ±{SCALE}")


if __name__ == "__main__":
    main()
