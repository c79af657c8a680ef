#!/usr/bin/python3
"""Drives every robot of robot_fleet.test through robot.launch's wiring.

For each robot (namespace = tf_prefix = its robot file's name):
- tf chains odom -> base_link -> every wheel link (drive wheels, caster wheels, passive wheels), the link names
  derived here from the robot file on the parameter server (wheel_link<i> per drive, caster_wheel_link<j>,
  passive_wheel_link<k> in name order);
- a command on nav_vel moves it, while robots not commanded stay where they are (no cross-talk: each robot has
  its own mux, base_driver and topics);
On one robot: a teleop_joy/cmd_vel command overrides nav_vel; safety/lock stops it although nav_vel goes on;
releasing the lock lets nav_vel drive again.
Synchronisation is on odometry messages with deadlines, never on sleeps.
"""
import math
import threading
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool
from tf2_msgs.msg import TFMessage

SPEED = 0.3          # commanded forward speed [m/s]
MOVED = 0.15         # a robot driving has gone at least this far [m]
STILL = 0.005        # a robot not driven moves less than this [m] (the simulator has no noise here)
DEADLINE = 60.0      # [s] for anything to happen, generous for 11 robots starting on 2 cores


class Robot(object):
    def __init__(self, name):
        self.name = name
        self.lock = threading.Lock()
        self.odom = None
        self.count = 0
        self.nav = rospy.Publisher("/%s/nav_vel" % name, Twist, queue_size=1)
        self.teleop = rospy.Publisher("/%s/teleop_joy/cmd_vel" % name, Twist, queue_size=1)
        self.safety = rospy.Publisher("/%s/safety/lock" % name, Bool, queue_size=1, latch=True)
        rospy.Subscriber("/%s/odometry/base_raw" % name, Odometry, self.on_odom)
        drives = rospy.get_param("/%s/motor_drives" % name)
        self.wheel_links = ["%s/wheel_link%d" % (name, i) for i in range(len(drives))]
        casters = rospy.get_param("/%s/casters" % name, {}) or {}
        passive = rospy.get_param("/%s/passive_wheels" % name, {}) or {}
        self.wheel_links += ["%s/caster_wheel_link%d" % (name, i) for i in range(len(casters))]
        self.wheel_links += ["%s/passive_wheel_link%d" % (name, i) for i in range(len(passive))]
        self.nav_cmd = None
        self.teleop_cmd = None
        self.joint_names = set()
        rospy.Subscriber("/%s/joint_states" % name, JointState, self.on_joints)

    def on_joints(self, msg):
        with self.lock:
            self.joint_names.update(msg.name)

    def on_odom(self, msg):
        with self.lock:
            self.odom = msg
            self.count += 1

    def state(self):
        with self.lock:
            if self.odom is None:
                return None, None, self.count
            p = self.odom.pose.pose.position
            return (p.x, p.y), self.odom.twist.twist.linear.x, self.count


def twist(vx):
    t = Twist()
    t.linear.x = vx
    return t


class FleetTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("fleet_test")
        cls.robots = [Robot(n) for n in rospy.get_param("~robots")]
        cls.by_name = dict((r.name, r) for r in cls.robots)
        cls.parent = {}
        cls.tf_lock = threading.Lock()
        rospy.Subscriber("/tf", TFMessage, cls.on_tf)
        rospy.Subscriber("/tf_static", TFMessage, cls.on_tf)
        cls.timer = rospy.Timer(rospy.Duration(0.05), cls.publish_commands)
        cls.wait_for(lambda: all(r.state()[0] is not None for r in cls.robots), "odometry from every robot")

    @classmethod
    def on_tf(cls, msg):
        with cls.tf_lock:
            for t in msg.transforms:
                cls.parent[t.child_frame_id.lstrip("/")] = t.header.frame_id.lstrip("/")

    @classmethod
    def publish_commands(cls, _event):
        for r in cls.robots:
            if r.nav_cmd is not None:
                r.nav.publish(twist(r.nav_cmd))
            if r.teleop_cmd is not None:
                r.teleop.publish(twist(r.teleop_cmd))

    @staticmethod
    def wait_for(condition, what, timeout=DEADLINE):
        end = rospy.get_time() + timeout
        rate = rospy.Rate(50)
        while not rospy.is_shutdown() and rospy.get_time() < end:
            if condition():
                return
            rate.sleep()
        raise AssertionError("timed out after %.0f s waiting for %s" % (timeout, what))

    def chain(self, frame):
        with self.tf_lock:
            out = [frame]
            while out[-1] in self.parent and len(out) < 50:
                out.append(self.parent[out[-1]])
            return out

    def wait_messages(self, robot, n):
        start = robot.state()[2]
        self.wait_for(lambda: robot.state()[2] >= start + n, "%d odometry messages of %s" % (n, robot.name))

    def test_0_joint_states_name_exactly_the_urdf_joints(self):
        for r in self.robots:
            robot = ET.fromstring(rospy.get_param("/%s/robot_description" % r.name))
            movable = set(j.get("name") for j in robot.findall("joint") if j.get("type") not in ("fixed", "floating"))
            self.assertIn("%s/wheel0" % r.name, movable)
            self.wait_for(lambda: movable <= r.joint_names, "joint states of every movable joint of %s" % r.name)
            with r.lock:
                self.assertEqual(r.joint_names, movable, "%s: joint_states names vs URDF joints" % r.name)

    def test_1_tf_reaches_every_wheel(self):
        for r in self.robots:
            for link in r.wheel_links:
                self.wait_for(lambda: "%s/odom" % r.name in self.chain(link), "tf %s/odom -> %s" % (r.name, link))
                c = self.chain(link)
                self.assertIn("%s/base_link" % r.name, c, "%s: %s" % (link, c))
                self.assertLess(c.index("%s/base_link" % r.name), c.index("%s/odom" % r.name))

    def test_2_nav_vel_moves_only_the_commanded_robots(self):
        half = [self.robots[0::2], self.robots[1::2]]
        for moving, still in (half, half[::-1]):
            # Robots to stay still must have stopped: they report zero speed.
            self.wait_for(lambda: all(abs(r.state()[1]) < 1e-4 for r in still), "the other robots at rest")
            start = dict((r.name, r.state()[0]) for r in self.robots)
            for r in moving:
                r.nav_cmd = SPEED
            for r in moving:
                self.wait_for(lambda: math.hypot(r.state()[0][0] - start[r.name][0],
                                                 r.state()[0][1] - start[r.name][1]) > MOVED,
                              "%s to drive on nav_vel" % r.name)
                self.assertGreater(r.state()[0][0] - start[r.name][0], MOVED * 0.9, "%s drives forward" % r.name)
            for r in moving:
                r.nav_cmd = None
            for r in still:
                p = r.state()[0]
                d = math.hypot(p[0] - start[r.name][0], p[1] - start[r.name][1])
                self.assertLess(d, STILL, "%s moved %.4f m on another robot's command" % (r.name, d))

    def test_3_teleop_overrides_and_safety_lock_stops(self):
        r = self.by_name[rospy.get_param("~override_robot")]
        r.nav_cmd = SPEED
        self.wait_for(lambda: r.state()[1] > 0.8 * SPEED, "%s to drive forward on nav_vel" % r.name)
        r.teleop_cmd = -SPEED
        self.wait_for(lambda: r.state()[1] < -0.8 * SPEED, "teleop to override nav_vel (drive backwards)")
        r.teleop_cmd = None
        self.wait_for(lambda: r.state()[1] > 0.8 * SPEED, "nav_vel to take over again after teleop's timeout")
        r.safety.publish(Bool(data=True))
        self.wait_for(lambda: abs(r.state()[1]) < 1e-3, "safety/lock to stop the robot", timeout=10.0)
        p0 = r.state()[0]
        self.wait_messages(r, 25)  # half a second of base_driver cycles with nav_vel still commanding
        p1 = r.state()[0]
        self.assertLess(math.hypot(p1[0] - p0[0], p1[1] - p0[1]), STILL, "locked robot crept")
        r.safety.publish(Bool(data=False))
        self.wait_for(lambda: r.state()[1] > 0.8 * SPEED, "nav_vel to drive again once the lock is released")
        r.nav_cmd = None


if __name__ == "__main__":
    rostest.rosrun("thorvald_bringup", "robot_fleet", FleetTest)
