#!/usr/bin/python3
"""Draws the figures of docs/architecture.md: packages.png (packages, layers and their package.xml arrows),
topics.png (nodes and topics in one robot namespace) and frames.png (frames, joints and sensor mounts).

    /usr/bin/python3 docs/figures/make_figures.py      # writes the PNGs next to this script

Arrows of packages.png are read from the package.xml files (build, export and run dependencies, not test ones);
the rest is drawn from the values in the robot files, sensor files and headers named in the figure captions.
"""
import glob
import os
import re
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, Rectangle  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from drawing import DPI, Graph, box  # noqa: E402
from frames_figure import draw_frames  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(HERE))

# ---- packages.png -------------------------------------------------------------------------------------------
BANDS = [  # top to bottom: (title, packages)
    ("bringup and simulator scenarios", ["thorvald_bringup", "thorvald_sim", "cotton_harvester_sim"]),
    ("applications", ["thorvald_navigation", "greenhouse_rail_nav", "cotton_harvester"]),
    ("platform: ROS-free core library + ROS adapters and nodes in each package",
     ["thorvald_twist_mux", "thorvald_teleop", "thorvald_model", "thorvald_can_devices", "thorvald_map",
      "thorvald_state_machine", "thorvald_base", "thorvald_gnss"]),
    ("shared by every package (arrows to it not drawn)", ["thorvald_common"]),
]
ROLES = {  # package: (nodes and adapters, core library)
    "thorvald_bringup": ("robot.launch, sim.launch, multi_robot.launch,\nsafety_heartbeat", "robot files (config/*.yaml)"),
    "thorvald_sim": ("thorvald_sim node, sim_hardware plugin,\ngnss_receiver", "thorvald_sim (MuJoCo worlds,\nsensor models, GNSS model)"),
    "cotton_harvester_sim": ("mujoco_rover_sim, mujoco_harvest,\nharvest_fleet_report", "cotton_harvester_sim\n(rover simulator, scorer)"),
    "thorvald_navigation": ("odom_fusion, headland_mapper,\nmap_localizer, headland_navigator,\nmap_publisher",
                            "thorvald_navigation (EKF, mapper,\nplanner, GoalRunner)"),
    "greenhouse_rail_nav": ("map_analyzer, rail_detector, surface_monitor,\nbumper, uv_mission",
                            "greenhouse_rail_nav, _mission"),
    "cotton_harvester": ("harvest_perception, harvest_state_machine,\nrover, manipulator",
                         "cotton_harvester_perception, _control"),
    "thorvald_twist_mux": ("twist_mux", "thorvald_twist_mux\n(priorities, locks)"),
    "thorvald_teleop": ("joy_teleop, joystick,\nkeyboard_teleop", "thorvald_teleop (pad, keys)"),
    "thorvald_model": ("urdf_generator,\npassive_joint_states", "thorvald_model (URDF)"),
    "thorvald_can_devices": ("can_device_sim,\nCAN hardware plugin", "thorvald_can_devices\n(bus, drives)"),
    "thorvald_state_machine": ("status publisher\n(thorvald_state_machine_ros)", "thorvald_state_machine"),
    "thorvald_base": ("base_driver, kinematics plugins,\nthorvald_base_ros", "thorvald_base\n(robot file, kinematics)"),
    "thorvald_map": ("message conversions (ros/)", "thorvald_map\n(grid, map files)"),
    "thorvald_common": ("thorvald_common_ros: parameter reader,\nbounded reads, runNode, waitFor",
                        "thorvald_common: stop signals,\ncommand line, bench statistics"),
    "thorvald_gnss": ("gpsd_client, nmea_tcp_feeder", "thorvald_gnss\n(gpsd fix -> NavSatFix)"),
}


def package_files():
    try:
        out = subprocess.run(["git", "-C", ROOT, "ls-files", "*package.xml"], capture_output=True, text=True,
                             check=True).stdout.split()
        return [os.path.join(ROOT, f) for f in out]
    except (OSError, subprocess.CalledProcessError):
        return glob.glob(os.path.join(ROOT, "*", "package.xml"))


def package_arrows():
    deps = {}
    for xml in package_files():
        text = open(xml, encoding="utf-8").read()
        name = re.search(r"<name>\s*(\w+)\s*</name>", text).group(1)
        deps[name] = set(re.findall(r"<(?:depend|build_depend|build_export_depend|exec_depend)>\s*(\w+)\s*<", text))
    return deps


def draw_packages(path):
    height = 0.4 + len(BANDS) * 2.75
    fig, ax = plt.subplots(figsize=(16, height))
    ax.set_xlim(0, 16)
    ax.set_ylim(0, height)
    ax.axis("off")
    where, band_h, w, h = {}, 2.55, 2.1, 1.55
    colours = ["#f3e1c7", "#d9e8f5", "#dcefd9", "#eeeeee"]
    for b, (title, pkgs) in enumerate(BANDS):
        y0 = height - (b + 1) * band_h - 0.2 * b
        box(ax, 0.1, y0, 15.8, band_h, colours[b], edge="#999999", radius=0.05)
        ax.text(0.25, y0 + band_h - 0.22, title, fontsize=11, weight="bold", va="top")
        w = min(2.45, (15.8 - 0.15 * (len(pkgs) + 1)) / len(pkgs))
        small = 0.88 if w < 2.3 else 1.0
        gap = (15.8 - len(pkgs) * w) / (len(pkgs) + 1)
        for i, p in enumerate(pkgs):
            x = 0.1 + gap + i * (w + gap)
            y = y0 + 0.25
            where[p] = (x + w / 2, y, y + h, b)
            box(ax, x, y, w, h, "white")
            ax.add_patch(Rectangle((x, y), w, 0.5, fc="#eeeeee", ec="#444444", lw=0.6))
            ax.text(x + w / 2, y + h - 0.15, p, ha="center", va="top", fontsize=9 * small, weight="bold")
            nodes, core = ROLES.get(p, ("", ""))
            ax.text(x + w / 2, y + 0.78, nodes, ha="center", va="center", fontsize=6.3 * small)
            ax.text(x + w / 2, y + 0.25, core, ha="center", va="center", fontsize=6.5 * small, style="italic")
    deps = package_arrows()
    for src, targets in sorted(deps.items()):
        for dst in sorted(targets):
            if src not in where or dst not in where:
                continue
            xs, ys_bottom, ys_top, bs = where[src]
            xd, yd_bottom, yd_top, bd = where[dst]
            up = bd < bs
            if bd == bs or BANDS[bd][1] == ["thorvald_common"]:
                continue  # inside one band (the platform's own arrows), or to the shared helpers: not drawn
            ax.add_patch(FancyArrowPatch((xs, ys_top if up else ys_bottom), (xd, yd_bottom if up else yd_top),
                                         arrowstyle="-|>", mutation_scale=10, lw=2.0 if up else 0.6,
                                         color="#cc2222" if up else "#555555", alpha=0.9 if up else 0.45,
                                         connectionstyle="arc3,rad=0.08"))
    ax.text(15.85, 0.02, "Arrows: 'depends on' (package.xml build, export and run dependencies; none drawn inside "
            "the platform band).  Grey: pointing down, allowed.  Red: pointing up, a violation that "
            "scripts/check_layers.sh reports.\nEach box: the package's nodes and ROS adapters above its ROS-free "
            "core library (italic, grey strip); the nodes depend on the library, never the reverse.",
            ha="right", va="bottom", fontsize=7.5)
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    plt.close(fig)


# ---- topics.png ---------------------------------------------------------------------------------------------
def draw_thorvald_topics(ax):
    ax.set_xlim(0, 17)
    ax.set_ylim(0, 9.4)
    ax.axis("off")
    ax.set_title("One Thorvald robot in its namespace /<robot>/ (names relative; the greenhouse robot's "
                 "mission shown)", fontsize=11, loc="left")
    g = Graph(ax)
    teleop, nav, safety, base, sensor = "#fde7c8", "#dcefd9", "#f6d5d5", "#dfeaf7", "#eadcf2"
    g.node("joystick", 1.2, 8.6, teleop)
    g.node("joy_teleop", 3.8, 8.6, teleop)
    g.node("uv_mission", 1.6, 6.0, nav)
    g.node("headland_navigator", 4.4, 6.9, nav)
    g.node("surface_monitor", 3.2, 3.4, safety)
    g.node("bumper", 3.2, 2.4, safety)
    g.node("safety_heartbeat", 3.2, 1.4, safety)
    g.node("twist_mux", 7.6, 5.0, base)
    g.node("base_driver", 10.6, 5.0, base)
    g.node("robot_state_publisher", 14.6, 6.3, base)
    g.node("passive_joint_states", 12.0, 7.6, base)
    g.node("odom_fusion", 14.6, 8.5, nav)
    g.node("sensors", 10.6, 1.2, sensor, text="thorvald_sim  (or the sensor drivers)")
    g.node("rail_detector", 7.2, 0.5, nav)
    g.node("map_localizer", 15.5, 3.0, nav)
    g.node("headland_mapper", 15.5, 1.3, nav)
    g.node("map_analyzer", 1.4, 4.6, nav)
    g.edge("joystick", "joy_teleop", "joy")
    g.edge("joy_teleop", "twist_mux", "teleop_joy/cmd_vel\nteleop_joy/joy_priority (lock)", rad=-0.15, frac=0.3)
    g.edge("headland_navigator", "twist_mux", "nav_vel", rad=-0.1)
    g.edge("uv_mission", "headland_navigator", "move_base (action)", rad=-0.2, frac=0.7, dy=0.15)
    g.edge("uv_mission", "twist_mux", "nav_vel", rad=0.05, frac=0.6)
    g.edge("map_analyzer", "uv_mission", "rail_targets", side_a="t", side_b="b")
    g.edge("surface_monitor", "twist_mux", "safety/lock", rad=0.1, frac=0.55)
    g.edge("bumper", "twist_mux", "bumper/lock", rad=0.12, frac=0.6)
    g.edge("safety_heartbeat", "twist_mux", "safety/heartbeat", rad=0.15, frac=0.62)
    g.edge("twist_mux", "base_driver", "twist_mux/cmd_vel")
    g.edge("base_driver", "odom_fusion", "odometry/base_raw", rad=0.15, frac=0.3)
    g.edge("base_driver", "robot_state_publisher", "joint_states", rad=0.05)
    g.edge("passive_joint_states", "robot_state_publisher", "joint_states", side_a="b", side_b="t", dy=0.0)
    g.edge("base_driver", "sensors", "joint_states (the simulator\nmoves the robot's joints)", side_a="b",
           side_b="t", frac=0.45)
    g.edge("sensors", "map_localizer", "scan", side_a="r", side_b="l", frac=0.5)
    g.edge("sensors", "headland_mapper", "scan", side_a="r", side_b="l", frac=0.5)
    g.edge("sensors", "rail_detector", "camera/depth/points", frac=0.5)
    g.edge("sensors", "surface_monitor", "ultrasonic/<name>", rad=-0.1, frac=0.45)
    g.edge("rail_detector", "uv_mission", "rail_detection, rail_pose", rad=-0.3, frac=0.12, side_a="l",
           side_b="b")
    ax.text(12.0, 4.75, "base_state, battery/<name>,\ndiagnostics, base_driver/* services",
            fontsize=7.2, va="top", color="#333333")
    ax.text(14.6, 9.05, "imu in (from the sensors); odometry/filtered, tf odom -> base_link out", fontsize=7.2,
            ha="center")
    ax.text(16.95, 3.5, "amcl_pose, tf map -> odom (map, initialpose in)", fontsize=7.2, ha="right")
    ax.text(15.5, 0.75, "map, map_metadata; save_map", fontsize=7.2, ha="center")
    ax.text(10.6, 0.62, "/clock, ground_truth/odom (scoring and tests only)", fontsize=7.2, ha="center")
    ax.text(1.6, 6.55, "uv_lights, mission/report", fontsize=7.2, ha="center")
    ax.text(16.9, 0.05, "orange: teleop; red: locks (highest priority first); green: navigation and missions; "
            "blue: the base stack; violet: sensors", fontsize=7, ha="right")


def draw_cotton_topics(ax):
    ax.set_xlim(0, 17)
    ax.set_ylim(0, 4.2)
    ax.axis("off")
    ax.set_title("The cotton rover in its namespace (cotton_harvester; thorvald_sim's MuJoCo rover or the real "
                 "ZED camera and serial controllers)", fontsize=11, loc="left")
    g = Graph(ax)
    g.node("camera", 1.4, 2.2, "#eadcf2", text="camera (ZED / sim)")
    g.node("harvest_perception", 5.0, 2.2, "#dcefd9")
    g.node("harvest_state_machine", 9.4, 2.2, "#dcefd9")
    g.node("rover", 14.0, 3.5, "#dfeaf7")
    g.node("manipulator", 14.0, 0.8, "#dfeaf7")
    g.node("rover_serial", 16.3, 3.5, "#eeeeee", w=1.2, text="serial")
    g.node("arm_serial", 16.3, 0.8, "#eeeeee", w=1.2, text="serial")
    g.edge("camera", "harvest_perception", "camera/color/image_raw\ncamera/depth/points")
    g.edge("harvest_perception", "harvest_state_machine", "bolls, end_effector/position")
    g.edge("harvest_state_machine", "rover", "rover/position_target", off=0.12, dy=0.3)
    g.edge("rover", "harvest_state_machine", "rover/position, rover/at_target", off=-0.12, dy=-0.3)
    g.edge("harvest_state_machine", "manipulator", "manipulator/target, manipulator/brush", off=0.12, dy=0.3)
    g.edge("manipulator", "harvest_state_machine", "manipulator/joint_states, manipulator/busy", off=-0.12,
           dy=-0.3)
    g.edge("rover", "rover_serial", "", style="<|-|>")
    g.edge("manipulator", "arm_serial", "", style="<|-|>")
    ax.text(14.0, 4.0, "cmd_vel in; wheel_odom out", fontsize=7.2, ha="center")
    ax.text(9.4, 1.6, "metrics, markers; start, stop", fontsize=7.2, ha="center")


def draw_topics(path):
    fig, (a, b) = plt.subplots(2, 1, figsize=(16, 14), gridspec_kw=dict(height_ratios=[9.4, 4.2]))
    draw_thorvald_topics(a)
    draw_cotton_topics(b)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    plt.close(fig)


if __name__ == "__main__":
    draw_packages(os.path.join(HERE, "packages.png"))
    draw_topics(os.path.join(HERE, "topics.png"))
    draw_frames(os.path.join(HERE, "frames.png"))
