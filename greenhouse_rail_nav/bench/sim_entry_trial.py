#!/usr/bin/python3
"""One forced entry onto the rails in the simulated greenhouse: drives the robot straight on at ~speed until the
range finders report an edge (caught), a wheel leaves its support (base_link drops, rolls or pitches: missed), or
base_link
is ~carried_x onto the rails with neither (carried). Prints one line `TRIAL {json}` and exits. Truth
(ground_truth/odom) only scores; surface_monitor's state is what the mission would see."""
import json
import math
import sys
import time

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from greenhouse_rail_nav.msg import SurfaceState


def main():
    rospy.init_node("sim_entry_trial")
    speed = float(rospy.get_param("~speed", 0.1))
    carried_x = float(rospy.get_param("~carried_x", 1.2))
    drop_m = float(rospy.get_param("~drop", 0.01))
    roll_rad = float(rospy.get_param("~roll", 0.02))
    timeout = float(rospy.get_param("~timeout", 300.0))  # wall time: the simulator runs slower under load
    label = rospy.get_param("~label", {})
    s = {"truth": None, "state": None, "edge": None}

    def on_truth(m):
        s["truth"] = m

    def on_state(m):
        s["state"] = m
        if s["edge"] is None and s["truth"] is not None and s.get("z0") is not None:
            names = [n for n, v in zip(m.sensors, m.surfaces) if v == SurfaceState.EDGE]
            if names:
                s["edge"] = (names, s["truth"].pose.pose.position.x)

    rospy.Subscriber("ground_truth/odom", Odometry, on_truth)
    rospy.Subscriber("surface_monitor/state", SurfaceState, on_state)
    pub = rospy.Publisher("nav_vel", Twist, queue_size=5)
    deadline = time.monotonic() + timeout
    while not rospy.is_shutdown() and (s["truth"] is None or s["state"] is None or
                                       s["state"].wheels != SurfaceState.FLOOR or s["state"].locked):
        if time.monotonic() > deadline:
            print("TRIAL " + json.dumps(dict(label, outcome="no_start")), flush=True)
            return 1
        time.sleep(0.05)
    s["z0"] = s["truth"].pose.pose.position.z
    rate = rospy.Rate(20)
    outcome, x_event = "carried", float("nan")
    while not rospy.is_shutdown():
        p = s["truth"].pose.pose
        q = p.orientation
        roll = math.atan2(2 * (q.w * q.x + q.y * q.z), 1 - 2 * (q.x * q.x + q.y * q.y))
        pitch = math.asin(max(-1.0, min(1.0, 2 * (q.w * q.y - q.z * q.x))))
        if s["edge"] is not None:
            outcome, x_event = "caught", s["edge"][1]
            break
        # base_link is on the front axle: a rear wheel leaving its support shows as pitch
        if p.position.z < s["z0"] - drop_m or abs(roll) > roll_rad or abs(pitch) > roll_rad:
            outcome, x_event = "missed", p.position.x
            break
        if p.position.x >= carried_x or time.monotonic() > deadline:
            outcome = "carried" if p.position.x >= carried_x else "timeout"
            x_event = p.position.x
            break
        t = Twist()
        t.linear.x = speed
        pub.publish(t)
        rate.sleep()
    for _ in range(10):
        pub.publish(Twist())
        rate.sleep()
    print("TRIAL " + json.dumps(dict(label, outcome=outcome, x=round(x_event, 3),
                                     sensors=s["edge"][0] if s["edge"] else [])), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
