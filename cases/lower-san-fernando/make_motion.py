#!/usr/bin/python3
"""pacoima-modified.csv from the source model's velocity record (README.md, "Sources").

    make_motion.py PacVel.txt pacoima-modified.csv

PacVel.txt: a title line, a line "count, dt", then one velocity (m/s) per line. The
acceleration is its central difference (one-sided at the ends); the first 16 s are kept
with a cosine taper over the last second.
"""
import sys

import numpy as np


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    try:
        lines = open(sys.argv[1]).read().split("\n")
        count, dt = (float(v) for v in lines[1].split(","))
        velocity = np.array([float(v) for v in lines[2:] if v.strip()])
    except (OSError, ValueError, IndexError) as error:
        sys.exit(f"make_motion.py: {sys.argv[1]}: {error}")
    if len(velocity) != int(count):
        sys.exit(f"make_motion.py: {sys.argv[1]}: {len(velocity)} values, header says {int(count)}")
    acceleration = np.gradient(velocity, dt)
    time = np.arange(len(velocity)) * dt
    keep = time <= 16.0 + 1e-9
    time, acceleration = time[keep], acceleration[keep]
    taper = time > 15.0
    acceleration[taper] *= 0.5 * (1.0 + np.cos(np.pi * (time[taper] - 15.0)))
    with open(sys.argv[2] + ".tmp", "w") as out:
        out.write(HEADER)
        for t, a in zip(time, acceleration):
            out.write(f"{t:.2f}, {a:.6e}\n")
    import os
    os.replace(sys.argv[2] + ".tmp", sys.argv[2])


HEADER = """# The horizontal base motion of cases/lower-san-fernando (docs/method.md §8): the
# "Modified Pacoima Dam" velocity record of J. Montgomery's FLAC2D model of the Lower
# San Fernando Dam (github.com/jmontgomery-au/FLAC2D-DamNDA, LSF_FLAC2D/PacVel.txt,
# commit d7492d1; MIT License, Copyright (c) 2025 Jack Montgomery), 1997 samples at
# 0.02 s, turned into acceleration by central differences (one-sided at the ends),
# its first 16 s kept (95 % of the Arias intensity is reached at 9.8 s; after 12 s
# |a| ≤ 0.062 g) with a cosine taper over the last second. Peak 0.509 g at 7.7 s.
# Regenerate: python3 make_motion.py PacVel.txt (cases/lower-san-fernando/README.md).
# time (s), acceleration (m/s2)
"""

if __name__ == "__main__":
    main()
