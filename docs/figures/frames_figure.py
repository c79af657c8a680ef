"""frames.png of docs/architecture.md: the tf tree, the 4WD4WS drives and joints, the greenhouse robot's sensor
mounts and the cotton rover's camera frame, arm axes and boll coordinates (drawn by make_figures.py)."""
import math

import matplotlib.pyplot as plt
from matplotlib.patches import Circle, Rectangle

from drawing import DPI, Graph, axes_arrows, out_of_page


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
