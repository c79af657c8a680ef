#!/usr/bin/python3
"""Draws the figures of docs/architecture.md: packages.png (packages, layers and their package.xml arrows),
topics.png (nodes and topics in one robot namespace) and frames.png (frames, joints and sensor mounts).

    /usr/bin/python3 docs/figures/make_figures.py      # writes the PNGs next to this script

Arrows of packages.png are read from the package.xml files (build, export and run dependencies, not test ones);
the rest is drawn from the values in the robot files, sensor files and headers named in the figure captions.
"""
import glob
import math
import os
import re
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle, FancyArrowPatch, FancyBboxPatch, Polygon, Rectangle  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DPI = 110

# ---- packages.png -------------------------------------------------------------------------------------------
BANDS = [  # top to bottom: (title, packages)
    ("bringup and simulator scenarios", ["thorvald_bringup", "thorvald_sim"]),
    ("applications", ["thorvald_navigation", "greenhouse_rail_nav", "cotton_harvester"]),
    ("platform: ROS-free core library + ROS adapters and nodes in each package",
     ["thorvald_twist_mux", "thorvald_teleop", "thorvald_model", "thorvald_can_devices", "thorvald_state_machine",
      "thorvald_base"]),
]
ROLES = {  # package: (nodes and adapters, core library)
    "thorvald_bringup": ("robot.launch, sim.launch, multi_robot.launch,\nsafety_heartbeat", "robot files (config/*.yaml)"),
    "thorvald_sim": ("thorvald_sim node, sim_hardware plugin", "thorvald_sim (MuJoCo worlds, sensors)"),
    "thorvald_navigation": ("odom_fusion, headland_mapper,\nmap_localizer, headland_navigator,\nmap_publisher",
                            "thorvald_navigation (EKF, mapper, planner)"),
    "greenhouse_rail_nav": ("map_analyzer, rail_detector, surface_monitor,\nbumper, uv_mission",
                            "greenhouse_rail_nav, _mission"),
    "cotton_harvester": ("harvest_perception, harvest_state_machine,\nrover, manipulator",
                         "cotton_harvester_perception, _control"),
    "thorvald_twist_mux": ("twist_mux", "thorvald_twist_mux (priorities, locks)"),
    "thorvald_teleop": ("joy_teleop, joystick, keyboard_teleop", "thorvald_teleop (pad, keys)"),
    "thorvald_model": ("urdf_generator, passive_joint_states", "thorvald_model (URDF)"),
    "thorvald_can_devices": ("can_device_sim, CAN hardware plugin", "thorvald_can_devices (bus, drives)"),
    "thorvald_state_machine": ("status publisher\n(thorvald_state_machine_ros)", "thorvald_state_machine"),
    "thorvald_base": ("base_driver, kinematics plugins,\nthorvald_base_ros", "thorvald_base (robot file, kinematics)"),
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


def box(ax, x, y, w, h, face, edge="#444444", lw=1.0, radius=0.02):
    ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle=f"round,pad=0,rounding_size={radius}", fc=face, ec=edge,
                                lw=lw))


def draw_packages(path):
    fig, ax = plt.subplots(figsize=(16, 8.6))
    ax.set_xlim(0, 16)
    ax.set_ylim(0, 8.6)
    ax.axis("off")
    where, band_h, w, h = {}, 2.55, 2.45, 1.55
    colours = ["#f3e1c7", "#d9e8f5", "#dcefd9"]
    for b, (title, pkgs) in enumerate(BANDS):
        y0 = 8.6 - (b + 1) * band_h - 0.2 * b
        box(ax, 0.1, y0, 15.8, band_h, colours[b], edge="#999999", radius=0.05)
        ax.text(0.25, y0 + band_h - 0.22, title, fontsize=11, weight="bold", va="top")
        gap = (15.8 - len(pkgs) * w) / (len(pkgs) + 1)
        for i, p in enumerate(pkgs):
            x = 0.1 + gap + i * (w + gap)
            y = y0 + 0.25
            where[p] = (x + w / 2, y, y + h, b)
            box(ax, x, y, w, h, "white")
            ax.add_patch(Rectangle((x, y), w, 0.5, fc="#eeeeee", ec="#444444", lw=0.6))
            ax.text(x + w / 2, y + h - 0.15, p, ha="center", va="top", fontsize=9, weight="bold")
            nodes, core = ROLES.get(p, ("", ""))
            ax.text(x + w / 2, y + 0.78, nodes, ha="center", va="center", fontsize=6.3)
            ax.text(x + w / 2, y + 0.25, core, ha="center", va="center", fontsize=6.5, style="italic")
    deps = package_arrows()
    for src, targets in sorted(deps.items()):
        for dst in sorted(targets):
            if src not in where or dst not in where:
                continue
            xs, ys_bottom, ys_top, bs = where[src]
            xd, yd_bottom, yd_top, bd = where[dst]
            up = bd < bs
            if bd == bs:
                continue  # inside one band (the platform's own arrows): not drawn
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
class Graph:
    """Node boxes and labelled topic arrows on one axis."""

    def __init__(self, ax):
        self.ax, self.pos = ax, {}

    def node(self, name, x, y, colour="#dfeaf7", w=None, text=None):
        w = w or max(1.5, 0.105 * len(text or name) + 0.3)
        self.pos[name] = (x, y, w)
        box(self.ax, x - w / 2, y - 0.28, w, 0.56, colour, radius=0.08)
        self.ax.text(x, y, text or name, ha="center", va="center", fontsize=8.5, weight="bold")

    def edge(self, a, b, label, rad=0.0, dy=0.0, colour="#333333", style="-|>", frac=0.5, side_a=None, side_b=None,
             off=0.0):
        (xa, ya, wa), (xb, yb, wb) = self.pos[a], self.pos[b]
        pa = self.anchor(xa, ya, wa, xb, yb, side_a)
        pb = self.anchor(xb, yb, wb, xa, ya, side_b)
        pa, pb = (pa[0], pa[1] + off), (pb[0], pb[1] + off)  # off: two arrows between the same boxes
        self.ax.add_patch(FancyArrowPatch(pa, pb, arrowstyle=style, mutation_scale=11, lw=1.0, color=colour,
                                          connectionstyle=f"arc3,rad={rad}", shrinkA=1, shrinkB=1))
        # The label sits on the arc (matplotlib's arc3: a quadratic Bezier through this control point).
        cx = (pa[0] + pb[0]) / 2 + rad * (pb[1] - pa[1])
        cy = (pa[1] + pb[1]) / 2 - rad * (pb[0] - pa[0])
        t = frac
        mx = (1 - t) ** 2 * pa[0] + 2 * t * (1 - t) * cx + t * t * pb[0]
        my = (1 - t) ** 2 * pa[1] + 2 * t * (1 - t) * cy + t * t * pb[1] + dy
        self.ax.text(mx, my, label, ha="center", va="center", fontsize=7.2, color=colour,
                     bbox=dict(fc="white", ec="none", pad=0.6, alpha=0.85))

    @staticmethod
    def anchor(x, y, w, tx, ty, side):
        side = side or ("r" if tx > x + w / 2 else "l" if tx < x - w / 2 else "t" if ty > y else "b")
        return {"r": (x + w / 2, y), "l": (x - w / 2, y), "t": (x, y + 0.28), "b": (x, y - 0.28)}[side]


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



# ---- frames.png ---------------------------------------------------------------------------------------------
def axes_arrows(ax, x, y, vx, vy, names, colours=("#cc2222", "#228822"), scale=0.25, fs=8):
    """Two axis arrows from (x, y) along (vx[0], vy[0]) and (vx[1], vy[1]) with their names."""
    for (dx, dy), name, c in zip(zip(vx, vy), names, colours):
        ax.annotate("", (x + scale * dx, y + scale * dy), (x, y),
                    arrowprops=dict(arrowstyle="-|>", color=c, lw=1.6, mutation_scale=10))
        ax.text(x + 1.2 * scale * dx, y + 1.2 * scale * dy, name, color=c, fontsize=fs, ha="center",
                va="center", weight="bold")


def out_of_page(ax, x, y, name, r=0.035, into=False, colour="#2244cc", fs=8, dx=0.07):
    ax.add_patch(Circle((x, y), r, fill=False, ec=colour, lw=1.3))
    if into:
        ax.plot([x - r * 0.7, x + r * 0.7], [y - r * 0.7, y + r * 0.7], color=colour, lw=1.1)
        ax.plot([x - r * 0.7, x + r * 0.7], [y + r * 0.7, y - r * 0.7], color=colour, lw=1.1)
    else:
        ax.add_patch(Circle((x, y), r * 0.3, color=colour))
    ax.text(x + dx, y, name, color=colour, fontsize=fs, va="center", weight="bold")


def draw_tf_tree(ax):
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 7)
    ax.axis("off")
    ax.set_title("(a) The tf tree of one robot (REP 105); <p>/ is the robot's tf_prefix", fontsize=10, loc="left")
    g = Graph(ax)
    g.node("map", 1.3, 6.2, "#eeeeee", text="map  (one per world)")
    g.node("odom", 1.3, 4.7, "#dfeaf7", text="<p>/odom")
    g.node("base_link", 1.3, 3.2, "#dfeaf7", text="<p>/base_link")
    g.edge("map", "odom", "map_localizer\n(thorvald_sim: publish_map_tf)", frac=0.5)
    g.edge("odom", "base_link", "base_driver (enable_odom_tf)\nor odom_fusion (publish_tf)", frac=0.5)
    children = [("leg", 6.3, "#dcefd9", "<p>/leg_link<i>   (joint steering<i>: revolute about z)"),
                ("wheel", 5.4, "#dcefd9", "<p>/wheel_link<i>   (joint wheel<i>: continuous about y)"),
                ("module", 4.3, "#dcefd9", "<p>/steering_module_link<i>, battery_<name>, pipe_<name>, ..."),
                ("casters", 3.2, "#dcefd9", "<p>/caster_swivel_link<i>, caster_wheel_link<i> (passive)"),
                ("sensor", 2.1, "#eadcf2", "<p>/<sensor>   (laser, camera, front_left, ..., imu)"),
                ("optical", 1.2, "#eadcf2", "<p>/camera_optical   (z forward, x right, y down)")]
    for name, y, colour, text in children:
        g.node(name, 6.4, y, colour, w=6.6, text=text)
    for n in ("leg", "module", "casters", "sensor"):
        g.edge("base_link", n, "", side_a="r", side_b="l")
    g.edge("leg", "wheel", "", side_a="b", side_b="t")
    g.edge("sensor", "optical", "", side_a="b", side_b="t")
    ax.text(0.05, 1.7, "links: robot_state_publisher\n(URDF of urdf_generator,\njoint_states of base_driver\n"
            "and passive_joint_states)\nsensors: thorvald_sim's static\ntf from its sensor file", fontsize=7.3,
            va="center")


def draw_4wd4ws(ax):
    """Top view of thorvald_bringup/config/a_4wd4ws_wide.yaml."""
    drives = [(-0.678, -0.75), (0.678, -0.75), (0.678, 0.75), (-0.678, 0.75)]
    ax.set_xlim(-1.45, 1.45)
    ax.set_ylim(-1.25, 1.15)
    ax.set_aspect("equal")
    ax.set_title("(b) 4WD4WS Thorvald from above (a_4wd4ws_wide.yaml): drives, joints, axes", fontsize=10,
                 loc="left")
    ax.add_patch(Rectangle((-0.678, -0.75), 1.356, 1.5, fill=False, ec="#999999", lw=1, ls="--"))
    for i, (x, y) in enumerate(drives):
        ax.add_patch(Rectangle((x - 0.2, y - 0.05), 0.4, 0.1, fc="#333333"))
        out_of_page(ax, x, y, "", r=0.03)
        side = 1 if y > 0 else -1
        ax.annotate("", (x - 0.1 * side, y + side * 0.26), (x + 0.1 * side, y + side * 0.26),  # counter-clockwise
                    arrowprops=dict(arrowstyle="-|>", connectionstyle="arc3,rad=0.5", color="#2244cc", lw=1.0))
        ax.annotate("", (x, y + 0.2), (x, y), arrowprops=dict(arrowstyle="-|>", color="#228822", lw=1.4))
        ax.text(x + (0.25 if x > 0 else -0.25), y, f"drive{i}\n({x:+.3f}, {y:+.2f})\nsteering{i}, wheel{i}",
                fontsize=7.5, ha="left" if x > 0 else "right", va="center")
    axes_arrows(ax, 0, 0, (1, 0), (0, 1), ("x", "y"), scale=0.35)
    out_of_page(ax, 0, 0, "z (up)", r=0.03, dx=-0.3)
    ax.text(0.02, -0.1, "base_link", fontsize=8, va="top")
    ax.text(-1.43, -1.22, "Steering<i> turns the leg about +z (counter-clockwise from above, 0: wheel along x,\n"
            "limits +-str_lim); wheel<i> turns about the leg's +y (green): positive rolls the robot forward.\n"
            "Drives are numbered as in the robot file (drive0 rear right, counter-clockwise); positions [m].",
            fontsize=7.2, va="bottom")
    ax.set_xlabel("x [m] (forward)")
    ax.set_ylabel("y [m] (left)")
    ax.tick_params(labelsize=7)



GREENHOUSE_SENSORS = [  # thorvald_sim/config/sensors_greenhouse.yaml: name, x, y, z, pitch [rad]
    ("laser", 0.45, 0.0, 0.62, 0.0), ("front_right", 0.52, -0.30, 0.35, 1.5708),
    ("front_left", 0.52, 0.30, 0.35, 1.5708), ("mid_right", 0.0, -0.30, 0.35, 1.5708),
    ("mid_left", 0.0, 0.30, 0.35, 1.5708), ("camera", 0.35, 0.0, 0.70, 0.70), ("imu", 0.0, 0.0, 0.5, 0.0)]


def draw_greenhouse(ax_top, ax_side):
    """The greenhouse rail robot (greenhouse_rail_robot.yaml, greenhouse_frame.urdf, sensors_greenhouse.yaml)."""
    ax_top.set_title("(c) Greenhouse rail robot: base_link on the floor under the drive axle; sensor mounts",
                     fontsize=10, loc="left")
    for ax in (ax_top, ax_side):
        ax.set_aspect("equal")
        ax.tick_params(labelsize=7)
        ax.add_patch(Rectangle((-0.85, -0.46 if ax is ax_top else 0.558), 1.05, 0.92 if ax is ax_top else 0.004,
                               fill=False, ec="#999999", ls="--"))
    ax_top.set_xlim(-1.05, 1.0)
    ax_top.set_ylim(-0.62, 0.62)
    for y in (-0.20, 0.20):  # drive wheels 350 mm, 60 mm wide; rail wheels 0.075 m outboard
        ax_top.add_patch(Rectangle((-0.175, y - 0.03), 0.35, 0.06, fc="#333333"))
        ax_top.add_patch(Rectangle((-0.12, y + (0.075 if y > 0 else -0.075) - 0.02), 0.24, 0.04, fc="#777777"))
    for y in (0.15, -0.15):
        ax_top.add_patch(Circle((-0.80, y), 0.04, fc="#777777"))
    for name, x, y, z, pitch in GREENHOUSE_SENSORS:
        ax_top.plot(x, y, "o", color="#7a3fa0", ms=4)
        dy = {"camera": -0.08, "laser": 0.05}.get(name, 0.05 if y >= 0 else -0.07)
        ax_top.text(x + 0.03 - (0.12 if name == "camera" else 0), y + dy, name, fontsize=7, color="#7a3fa0")
    axes_arrows(ax_top, 0, 0, (1, 0), (0, 1), ("x", "y"), scale=0.22)
    ax_top.text(-1.03, -0.6, "drive0 right (y -0.20), drive1 left (+0.20): floor wheels r 0.175 m (dark), rail "
                "wheels r 0.12 m\n(grey, 0.075 m outboard, on pipes 0.55 m apart); casters at x -0.80; dashed: "
                "the frame's top plate.", fontsize=6.8, va="bottom")
    ax_side.set_xlim(-1.05, 1.0)
    ax_side.set_ylim(-0.05, 1.02)
    ax_side.axhline(0, color="#8b6d4a", lw=2)
    ax_side.add_patch(Circle((0, 0.175), 0.175, fill=False, ec="#333333", lw=1.5))
    ax_side.add_patch(Circle((-0.80, 0.0625), 0.0625, fill=False, ec="#777777", lw=1.2))
    for name, x, y, z, pitch in GREENHOUSE_SENSORS:
        if y > 0:
            continue  # left twins sit behind the right ones
        ax_side.plot(x, z, "o", color="#7a3fa0", ms=4)
        d = 0.18
        ax_side.annotate("", (x + d * math.cos(pitch), z - d * math.sin(pitch)), (x, z),
                         arrowprops=dict(arrowstyle="-|>", color="#cc2222", lw=1.2))
        label = {"front_right": "front_ / mid_ ultrasonic (x down)", "mid_right": "", "camera":
                 "camera (pitched 0.70 rad down)"}.get(name, name)
        ax_side.text(x + 0.04, z + 0.04, label, fontsize=7, color="#7a3fa0")
    axes_arrows(ax_side, 0, 0, (1, 0), (0, 1), ("x", "z"), colours=("#cc2222", "#2244cc"), scale=0.22)
    ax_side.text(-1.03, 0.98, "side view (red: each sensor's x axis, the direction it looks)", fontsize=7,
                 va="top")


def draw_cotton(ax):
    """The cotton rover seen from behind, looking forward along the row (cotton_harvester rover_sim.h,
    harvest_decision.h, msg/Boll.msg, config/harvest_mujoco_nodes.yaml)."""
    ax.set_title("(d) Cotton rover from behind: camera frame, arm axes, boll coordinates", fontsize=10, loc="left")
    ax.set_aspect("equal")
    ax.set_xlim(-1.6, 1.6)
    ax.set_ylim(-0.1, 2.75)
    ax.tick_params(labelsize=7)
    ax.axhline(0, color="#8b6d4a", lw=2)
    for x in (-0.91, 0.91):  # wheels' centres half a wheel width inside the 2.12 m outer width
        ax.add_patch(Rectangle((x - 0.15, 0), 0.30, 0.61, fc="#444444"))
    cam_x, cam_z = 0.0, 2.20  # drawn with the rover's left on the left: camera x points left
    ax.add_patch(Rectangle((cam_x - 0.08, cam_z), 0.16, 0.08, fc="#7a3fa0"))
    axes_arrows(ax, cam_x, cam_z, (-1, 0), (0, -1), ("x", "z"), colours=("#cc2222", "#2244cc"), scale=0.35)
    out_of_page(ax, cam_x + 0.12, cam_z + 0.2, "y (forward, into the page)", into=True, colour="#228822")
    arm_x = cam_x + 0.55  # the arm's vertical axis at camera x = -0.55: 0.55 m to the rover's right
    ax.plot([arm_x, arm_x], [cam_z - 0.30, cam_z - 1.93], color="#999999", lw=6, alpha=0.5)
    ax.plot([arm_x, arm_x - 0.70], [cam_z - 1.1, cam_z - 1.1], color="#e08a1e", lw=4)
    ax.add_patch(Rectangle((arm_x - 0.70 - 0.05, cam_z - 1.1 - 0.08), 0.10, 0.08, fc="#e08a1e"))
    ax.annotate("", (arm_x - 0.70, cam_z - 1.25), (arm_x, cam_z - 1.25),
                arrowprops=dict(arrowstyle="-|>", color="#e08a1e", lw=1.2))
    ax.text(arm_x - 0.35, cam_z - 1.38, "horizontal: extension 0..0.70 m\n(towards +x)", fontsize=7,
            ha="center", va="top", color="#b0650a")
    ax.text(arm_x + 0.06, cam_z - 0.5, "vertical: end effector\n0.30..1.93 m below\nthe camera (+z)",
            fontsize=7, color="#555555")
    bx, bz = -0.1, 1.25  # camera x = +0.10: inside the arm's reach (-0.55 .. +0.15)
    ax.add_patch(Circle((bx, bz), 0.04, fc="white", ec="#333333"))
    ax.plot([cam_x, bx], [bz, bz], ls=":", color="#cc2222")
    ax.plot([bx, bx], [cam_z, bz], ls=":", color="#2244cc")
    ax.text(bx - 0.05, bz - 0.1, "boll (x_b, y_b, z_b)\nin the camera frame", fontsize=7, ha="center",
            va="top")
    ax.text(-1.58, 2.72, "camera 2.20 m up, 1.30 m ahead of the articulation joint; optical frame: x across the "
            "row\ntowards the rover's left (the arm extends along +x), y forward along the row, z down (depth).",
            fontsize=7, va="top")
    ax.set_xlabel("across the row [m] (rover's left on the left)")


def draw_frames(path):
    fig = plt.figure(figsize=(16, 15))
    gs = fig.add_gridspec(3, 2, height_ratios=[1.0, 0.62, 0.55])
    draw_tf_tree(fig.add_subplot(gs[0, 0]))
    draw_4wd4ws(fig.add_subplot(gs[0, 1]))
    draw_greenhouse(fig.add_subplot(gs[1, 0]), fig.add_subplot(gs[2, 0]))
    draw_cotton(fig.add_subplot(gs[1:, 1]))
    fig.tight_layout()
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    plt.close(fig)


if __name__ == "__main__":
    draw_packages(os.path.join(HERE, "packages.png"))
    draw_topics(os.path.join(HERE, "topics.png"))
    draw_frames(os.path.join(HERE, "frames.png"))
