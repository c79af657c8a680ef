#!/usr/bin/python3
"""Draws the odometry_bench paths of every seed (truth, least squares, random pairs) into one PNG.

Usage: plot_odometry_paths.py <paths.csv> <out.png>; the CSV has columns seed,t,truth_x,truth_y,ls_x,ls_y,paper_x,paper_y.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    seeds = {}
    with open(sys.argv[1], newline="") as f:
        for row in csv.DictReader(f):
            seeds.setdefault(int(row["seed"]), []).append(row)
    fig, ax = plt.subplots(figsize=(8, 7))
    for i, (seed, rows) in enumerate(sorted(seeds.items())):
        col = lambda k: [float(r[k]) for r in rows]  # noqa: E731
        if i == 0:
            ax.plot(col("truth_x"), col("truth_y"), "k-", lw=2.0, label="truth")
        ax.plot(col("ls_x"), col("ls_y"), "-", color="tab:blue", lw=0.8, label="least squares" if i == 0 else None)
        ax.plot(col("paper_x"), col("paper_y"), "-", color="tab:red", lw=0.8, label="random pairs (paper)" if i == 0 else None)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("odometry_bench: Figure 7 robot, %d seeds" % len(seeds))
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.savefig(sys.argv[2], dpi=120, bbox_inches="tight")
    return 0


if __name__ == "__main__":
    sys.exit(main())
