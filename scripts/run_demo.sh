#!/usr/bin/env bash
# The demo: installs what is missing, builds the workspace, and runs the paper's odometry experiment in
# simulation: the Figure 7 six-wheel robot drives a 77 s loop in x, y and yaw, first in MuJoCo (the body moves by
# contact physics), then on base_driver's joint simulator with encoder quantisation, noise, a 1% radius error on
# two wheels and one slipping wheel. It prints distances and end-point errors of ground truth, the least-squares
# and the paper's random-pairs odometry, and writes plots of the paths to demo_output/. Then the two robots at
# work, headless in MuJoCo: the greenhouse robot's UV cycle on 2 short rail sets (it maps the headland, analyses the
# map, localises, navigates, enters and treats each rail set) and the cotton rover's potted harvest run (Table 2).
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="/usr/bin:$PATH"
"$src/scripts/install_deps.sh"
echo "== building the workspace (first time: several minutes on 2 cores)"
"$src/scripts/build.sh"
# shellcheck disable=SC1091
set +u; source "$src/.ws/devel/setup.bash"; set -u  # ROS setup scripts read unset variables
mkdir -p "$src/demo_output"
cd "$src/demo_output"
echo "== the paper's odometry experiment in MuJoCo: Figure 7 robot (thorvald_model's URDF), 77 s loop"
rosrun thorvald_model urdf_generator --config "$src/thorvald_bringup/config/figure7_6wd6ws_asymmetric.yaml" \
  --tf-prefix '' --robot-name figure7 >figure7.urdf
rosrun thorvald_sim odometry_demo --urdf figure7.urdf --csv odometry_mujoco.csv --png odometry_mujoco.png
echo "== the same loop on base_driver's joint simulator with corrupted readings (5 seeds)"
rosrun thorvald_base odometry_bench --seeds 5 --csv odometry_joint_sim.csv
/usr/bin/python3 "$src/thorvald_sim/scripts/plot_demo_paths.py" odometry_joint_sim.csv odometry_joint_sim.png \
  "Figure 7 robot, 77 s loop, joint simulator with corrupted readings (seed 1)"
echo "== cost of one control cycle"
rosrun thorvald_base cycle_bench --cycles 5000
echo "== the greenhouse robot's UV cycle in MuJoCo: 2 rail sets of 5 m (it maps the headland first; a few minutes)"
uv_rc=0
rosrun greenhouse_rail_nav uv_mission_bench --rail-sets 2 --rail-length 5 --out "$src/demo_output/uv_mission" || uv_rc=$?
echo "== the cotton rover's potted harvest in MuJoCo: six plants, three bolls each (Table 2), ideal sensors and plants"
rosrun cotton_harvester_sim harvest_bench --realism ideal --potted-runs 1 --field-runs 0 --png cotton_path.png \
  --debug-image cotton_frame.png
echo "== done: plots in demo_output/ (odometry_mujoco.png, odometry_joint_sim.png, uv_mission/, cotton_path.png," \
  "cotton_frame.png)"
if [ "$uv_rc" -ne 0 ]; then
  echo "== the greenhouse robot's UV cycle FAILED (uv_mission_bench exit $uv_rc): see demo_output/uv_mission/"
  exit "$uv_rc"
fi
