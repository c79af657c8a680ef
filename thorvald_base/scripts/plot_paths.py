#!/usr/bin/python3
"""Plots the true path and both odometry paths written by odometry_bench --csv into a PNG."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(src, dst, title):
    cols = {}
    with open(src) as f:
        for row in csv.DictReader(f):
            for k, v in row.items():
                cols.setdefault(k, []).append(float(v))
    fig, ax = plt.subplots(figsize=(8, 6))
    ax.plot(cols["truth_x"], cols["truth_y"], "k-", lw=2, label="truth")
    ax.plot(cols["ls_x"], cols["ls_y"], "b--", label="least-squares odometry")
    ax.plot(cols["paper_x"], cols["paper_y"], "r:", label="random-pairs odometry (paper)")
    ax.plot(cols["truth_x"][0], cols["truth_y"][0], "go", label="start")
    ax.set_aspect("equal")
    ax.grid(True)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title)
    ax.legend(loc="best")
    fig.tight_layout()
    fig.savefig(dst, dpi=110)
    print(f"wrote {dst}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3] if len(sys.argv) > 3 else "odometry")
