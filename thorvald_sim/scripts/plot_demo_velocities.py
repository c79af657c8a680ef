#!/usr/bin/python3
"""Plots the velocities odometry_demo wrote, as the paper's Figure 9: commanded and estimated vx, vy and wz over
time, per estimator, with the ground truth."""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_demo_paths import read_columns  # noqa: E402


def main():
    if len(sys.argv) not in (3, 4):
        sys.stderr.write("usage: plot_demo_velocities.py PATHS.csv OUT.png [TITLE]\n")
        return 2
    cols = read_columns(sys.argv[1])
    fig, axes = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    for ax, (key, label) in zip(axes, (("vx", "vx [m/s]"), ("vy", "vy [m/s]"), ("wz", "wz [rad/s]"))):
        ax.plot(cols["t"], cols["cmd_" + key], "g-", linewidth=2, label="commanded")
        ax.plot(cols["t"], cols["truth_" + key], "k-", linewidth=1, label="ground truth")
        ax.plot(cols["t"], cols["ls_" + key], "b--", linewidth=1, label="least squares")
        ax.plot(cols["t"], cols["paper_" + key], "r:", linewidth=1, label="random pairs (paper)")
        ax.set_ylabel(label)
        ax.grid(True)
    axes[0].legend(loc="upper right", fontsize="small")
    axes[-1].set_xlabel("t [s]")
    axes[0].set_title(sys.argv[3] if len(sys.argv) == 4 else "Figure 7 robot, 77 s loop in MuJoCo")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main())
