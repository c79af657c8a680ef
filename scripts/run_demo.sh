#!/usr/bin/env bash
# The demo: installs what is missing, builds the workspace, and runs the paper's odometry experiment in
# simulation: the Figure 7 six-wheel robot drives a 77 s loop in x, y and yaw on base_driver's joint simulator,
# with encoder quantisation, noise, a 1% radius error on two wheels and one slipping wheel. It prints the distance
# and end-point error of the least-squares and the paper's random-pairs odometry, and writes a plot of the paths
# to demo_output/odometry_paths.png.
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="/usr/bin:$PATH"
"$src/scripts/install_deps.sh"
echo "== building the workspace (first time: several minutes on 2 cores)"
"$src/scripts/build.sh" >"$src/.ws/demo_build.log" 2>&1 || { tail -40 "$src/.ws/demo_build.log"; exit 1; }
# shellcheck disable=SC1091
set +u; source "$src/.ws/devel/setup.bash"; set -u  # ROS setup scripts read unset variables
mkdir -p "$src/demo_output"
echo "== odometry experiment (Figure 7 robot, 77 s loop, 5 seeds)"
rosrun thorvald_base odometry_bench --seeds 5 --csv "$src/demo_output/odometry_paths.csv"
echo "== cost of one control cycle"
rosrun thorvald_base cycle_bench --cycles 5000
/usr/bin/python3 "$src/thorvald_base/scripts/plot_paths.py" "$src/demo_output/odometry_paths.csv" \
  "$src/demo_output/odometry_paths.png" "Figure 7 robot, 77 s loop: truth and odometry (seed 1)"
echo "== done: plot in demo_output/odometry_paths.png"
