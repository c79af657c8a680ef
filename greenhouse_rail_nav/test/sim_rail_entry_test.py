#!/usr/bin/python3
"""Drives the simulated greenhouse robot onto a rail set by contact and back, through the velocity mux (nav_vel), and
checks what surface_monitor and the physics did: the wheel radius switched to the rail wheels' on the rails and back
to the floor wheels' on the floor, the measured speed and base_driver's odometry matching the command on both
surfaces, base_link level, no edge reported and no safety lock on an aligned entry. Truth (ground_truth/odom) is used
only to score."""
import math
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool

from greenhouse_rail_nav.msg import SurfaceState


class Recorder:
    """Latest messages and what happened over the whole run (height band, lateral offset, edges, locks)."""

    def __init__(self):
        self.mutex = threading.Lock()
        self.truth = None
        self.odom = None
        self.state = None
        self.z0 = None
        self.z_min = self.z_max = None
        self.max_abs_y = 0.0
        self.max_tilt = 0.0  # largest |pitch| or |roll| [rad]: base_link is on the front axle, the rear shows as pitch
        self.edges = []
        self.locks = 0
        self.lock_reasons = set()
        self.lock = None
        self.radii = []
        self.trace = []  # (x, y, z, ranges) every 0.1 s of simulated time, printed when a check fails

    def on_truth(self, m):
        with self.mutex:
            self.truth = m
            z, y = m.pose.pose.position.z, m.pose.pose.position.y
            q = m.pose.pose.orientation
            pitch = math.asin(max(-1.0, min(1.0, 2 * (q.w * q.y - q.z * q.x))))
            roll = math.atan2(2 * (q.w * q.x + q.y * q.z), 1 - 2 * (q.x * q.x + q.y * q.y))
            if self.z0 is not None:
                self.max_tilt = max(self.max_tilt, abs(pitch), abs(roll))
                self.z_min = z if self.z_min is None else min(self.z_min, z)
                self.z_max = z if self.z_max is None else max(self.z_max, z)
                self.max_abs_y = max(self.max_abs_y, abs(y))

    def on_odom(self, m):
        with self.mutex:
            self.odom = m

    def on_state(self, m):
        with self.mutex:
            self.state = m
            for name, s in zip(m.sensors, m.surfaces):
                if s == SurfaceState.EDGE and self.z0 is not None:
                    self.edges.append((name, self.truth.pose.pose.position.x if self.truth else float("nan")))
            if not self.radii or self.radii[-1] != m.wheel_radius:
                self.radii.append(m.wheel_radius)
            if self.truth and (not self.trace or m.header.stamp.to_sec() - self.trace[-1][0] >= 0.1):
                p = self.truth.pose.pose.position
                self.trace.append((m.header.stamp.to_sec(), round(p.x, 3), round(p.y, 3), round(p.z, 4),
                                   [round(r, 3) for r in m.ranges], list(m.surfaces)))

    def on_lock(self, m):
        # Before the range finders' first readings the lock is engaged (silent sensors): count from the start.
        with self.mutex:
            self.lock = m.data
            if m.data and self.z0 is not None:
                self.locks += 1
                if self.state is not None:
                    self.lock_reasons.add(self.state.reason)


class SimRailEntry(unittest.TestCase):
    def setUp(self):
        self.speed = float(rospy.get_param("~speed"))
        self.rail_speed = float(rospy.get_param("~rail_speed"))
        self.enter_x = float(rospy.get_param("~enter_x"))
        self.exit_x = float(rospy.get_param("~exit_x"))
        self.floor_r = float(rospy.get_param("~floor_wheel_radius"))
        self.rail_r = float(rospy.get_param("~rail_wheel_radius"))
        self.max_dz = float(rospy.get_param("~max_height_change"))
        self.max_y = float(rospy.get_param("~max_lateral"))
        self.max_tilt = float(rospy.get_param("~max_tilt"))
        self.speed_tol = float(rospy.get_param("~speed_tolerance"))
        self.deadline = time.monotonic() + float(rospy.get_param("~timeout"))
        self.rec = Recorder()
        rospy.Subscriber("ground_truth/odom", Odometry, self.rec.on_truth)
        rospy.Subscriber("odometry/base_raw", Odometry, self.rec.on_odom)
        rospy.Subscriber("surface_monitor/state", SurfaceState, self.rec.on_state)
        rospy.Subscriber("safety/lock", Bool, self.rec.on_lock)
        self.pub = rospy.Publisher("nav_vel", Twist, queue_size=5)

    def tearDown(self):
        with self.rec.mutex:
            for row in self.rec.trace:
                print("trace t=%.1f x=%.3f y=%.3f z=%.4f ranges=%s surfaces=%s" % row)

    def wait_for(self, what, condition):
        while not condition():
            self.assertLess(time.monotonic(), self.deadline, "timed out waiting for " + what)
            self.assertFalse(rospy.is_shutdown())
            time.sleep(0.02)

    def truth_x(self):
        with self.rec.mutex:
            return self.rec.truth.pose.pose.position.x

    def drive_until(self, vx, what, done):
        """Commands vx [m/s] straight on at 20 Hz (simulated time) until done()."""
        rate = rospy.Rate(20)
        while not done():
            self.assertLess(time.monotonic(), self.deadline, "timed out driving " + what)
            self.assertFalse(rospy.is_shutdown())
            t = Twist()
            t.linear.x = vx
            self.pub.publish(t)
            rate.sleep()

    def stop(self, settle_s=1.0):
        end = rospy.Time.now() + rospy.Duration(settle_s)
        rate = rospy.Rate(20)
        while rospy.Time.now() < end:
            self.assertLess(time.monotonic(), self.deadline, "timed out stopping")
            self.pub.publish(Twist())
            rate.sleep()

    def measure_speed(self, vx, distance_m):
        """Drives vx until the truth has moved distance_m after a 0.3 m run-up; returns (truth speed, odometry
        distance / truth distance)."""
        x_start = self.truth_x()
        self.drive_until(vx, "the run-up", lambda: abs(self.truth_x() - x_start) >= 0.3)
        with self.rec.mutex:
            t0, p0 = self.rec.truth.header.stamp.to_sec(), self.rec.truth.pose.pose.position
            o0 = self.rec.odom.pose.pose.position
        self.drive_until(vx, "the measured stretch", lambda: abs(self.truth_x() - p0.x) >= distance_m)
        with self.rec.mutex:
            t1, p1 = self.rec.truth.header.stamp.to_sec(), self.rec.truth.pose.pose.position
            o1 = self.rec.odom.pose.pose.position
        truth_d = math.hypot(p1.x - p0.x, p1.y - p0.y)
        odom_d = math.hypot(o1.x - o0.x, o1.y - o0.y)
        return truth_d / max(t1 - t0, 1e-6), odom_d / truth_d

    def test_enter_rails_and_back(self):
        rec = self.rec
        self.wait_for("truth, odometry and the surface state",
                      lambda: rec.truth is not None and rec.odom is not None and rec.state is not None)
        self.wait_for("the floor under the wheels and the floor wheels' radius",
                      lambda: rec.state.wheels == SurfaceState.FLOOR and
                      abs(rec.state.wheel_radius - self.floor_r) < 1e-6)
        self.wait_for("the safety lock released", lambda: rec.lock is False)
        self.stop(1.0)
        with rec.mutex:
            rec.z0 = rec.truth.pose.pose.position.z
        floor_speed, floor_odom = self.measure_speed(self.speed, 0.2)
        rospy.loginfo("on the floor: %.3f m/s for %.3f commanded, odometry/truth %.3f", floor_speed, self.speed,
                      floor_odom)
        self.drive_until(self.speed, "onto the rails", lambda: self.truth_x() >= self.enter_x)
        self.stop()
        with rec.mutex:
            state = rec.state
        self.assertEqual(state.wheels, SurfaceState.RAIL, "wheel sensors on the rails: %s" % str(state))
        self.assertEqual(state.front, SurfaceState.RAIL, "front sensors on the rails: %s" % str(state))
        self.assertAlmostEqual(state.wheel_radius, self.rail_r, delta=1e-6)
        rail_speed, rail_odom = self.measure_speed(self.rail_speed, 0.5)
        rospy.loginfo("on the rails: %.3f m/s for %.3f commanded, odometry/truth %.3f", rail_speed, self.rail_speed,
                      rail_odom)
        self.stop()
        self.drive_until(-self.speed, "back onto the floor", lambda: self.truth_x() <= self.exit_x)
        self.stop()
        with rec.mutex:
            state = rec.state
        self.assertEqual(state.wheels, SurfaceState.FLOOR, "wheel sensors on the floor again: %s" % str(state))
        self.assertAlmostEqual(state.wheel_radius, self.floor_r, delta=1e-6)
        back_speed, back_odom = self.measure_speed(-self.speed, 0.2)
        self.stop(0.5)
        with rec.mutex:
            dz = (rec.z_min - rec.z0, rec.z_max - rec.z0)
            rospy.loginfo("base_link height change %.4f .. %.4f m, largest |y| %.4f m, largest tilt %.4f rad, radii %s, "
                          "edges %s, locks %d", dz[0], dz[1], rec.max_abs_y, rec.max_tilt, rec.radii, rec.edges[:5],
                          rec.locks)
            self.assertLessEqual(max(abs(dz[0]), abs(dz[1])), self.max_dz, "base_link did not stay level")
            self.assertLessEqual(rec.max_abs_y, self.max_y, "drifted off the centre line")
            self.assertLessEqual(rec.max_tilt, self.max_tilt, "pitched or rolled: a wheel left its support")
            self.assertEqual(rec.edges, [], "an edge was reported on an aligned entry")
            self.assertEqual(rec.locks, 0, "the safety lock engaged on an aligned entry: %s" % rec.lock_reasons)
            self.assertEqual([r for r in rec.radii if r > 0], [self.floor_r, self.rail_r, self.floor_r])
        for name, v, cmd, odo in (("floor", floor_speed, self.speed, floor_odom),
                                  ("rails", rail_speed, self.rail_speed, rail_odom),
                                  ("floor, reversing", back_speed, self.speed, back_odom)):
            self.assertAlmostEqual(v / cmd, 1.0, delta=self.speed_tol, msg="speed on the %s: %.3f m/s for %.3f" %
                                   (name, v, cmd))
            self.assertAlmostEqual(odo, 1.0, delta=self.speed_tol, msg="odometry/truth on the %s: %.3f" % (name, odo))


if __name__ == "__main__":
    rospy.init_node("sim_rail_entry_test")
    rostest.rosrun("greenhouse_rail_nav", "sim_rail_entry", SimRailEntry)
