#!/usr/bin/python3
"""Plots the paths odometry_demo wrote: ground truth, least squares and random pairs odometry."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_columns(path):
    """The CSV's columns by name, as floats."""
    cols = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            for k, v in row.items():
                cols.setdefault(k, []).append(float(v))
    return cols


def main():
    if len(sys.argv) not in (3, 4):
        sys.stderr.write("usage: plot_demo_paths.py PATHS.csv OUT.png [TITLE]\n")
        return 2
    cols = read_columns(sys.argv[1])
    fig, ax = plt.subplots(figsize=(8, 6))
    ax.plot(cols["truth_x"], cols["truth_y"], "k-", label="ground truth")
    ax.plot(cols["ls_x"], cols["ls_y"], "b--", label="least squares odometry")
    ax.plot(cols["paper_x"], cols["paper_y"], "r:", label="random pairs odometry (paper)")
    ax.plot([0], [0], "go", label="start")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")
    ax.grid(True)
    ax.legend()
    ax.set_title(sys.argv[3] if len(sys.argv) == 4 else "Figure 7 robot, 77 s loop in MuJoCo")
    fig.savefig(sys.argv[2], dpi=100)
    return 0


if __name__ == "__main__":
    sys.exit(main())
