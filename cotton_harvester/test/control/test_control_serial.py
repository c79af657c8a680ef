#!/usr/bin/python3
"""Rover and manipulator nodes end to end through the serial path (pseudo-terminals)."""
import math
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PointStamped, Twist
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Float64


class Latest:
    """Keeps the last message of a topic."""

    def __init__(self, topic, kind):
        self.msg = None
        self.count = 0
        self.lock = threading.Lock()
        self.sub = rospy.Subscriber(topic, kind, self._store, queue_size=20)

    def _store(self, msg):
        with self.lock:
            self.msg = msg
            self.count += 1

    def get(self):
        with self.lock:
            return self.msg


def wait_for(predicate, timeout_s):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline and not rospy.is_shutdown():
        if predicate():
            return True
        time.sleep(0.02)
    return False


class ControlSerialTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_control_serial")
        cls.position = Latest("rover/position", Float64)
        cls.truth = Latest("sim/rover_position", Float64)
        cls.joints = Latest("manipulator/joint_states", JointState)
        cls.busy = Latest("manipulator/busy", Bool)
        cls.rover_levels = []
        cls.diag_sub = rospy.Subscriber("/diagnostics", DiagnosticArray, cls._diagnostics, queue_size=50)
        cls.target_pub = rospy.Publisher("rover/position_target", Float64, queue_size=1, latch=True)
        cls.cmd_vel_pub = rospy.Publisher("cmd_vel", Twist, queue_size=1)
        cls.arm_pub = rospy.Publisher("manipulator/target", PointStamped, queue_size=1, latch=True)
        cls.vanish_pub = rospy.Publisher("simulated_controller/vanish", Float64, queue_size=1, latch=True)

    @classmethod
    def _diagnostics(cls, msg):
        for status in msg.status:
            if status.name.endswith("rover"):
                cls.rover_levels.append(status.level)

    def drive_to(self, target, timeout_s=60.0):
        self.target_pub.publish(Float64(target))
        # Within 6 cm of the target for real (the simulated rover), and the node's encoder agrees.
        return wait_for(lambda: self.truth.get() is not None and abs(self.truth.get().data - target) < 0.06
                        and self.position.get() is not None and abs(self.position.get().data - target) < 0.06,
                        timeout_s)

    def test_1_position_step_through_the_serial_path(self):
        self.assertTrue(wait_for(lambda: self.position.get() is not None, 20.0), "no rover/position")
        start = self.position.get().data
        self.assertTrue(self.drive_to(start + 0.4), "rover did not reach a 0.4 m step within 60 s")
        # Encoder through the serial link against the simulated truth: a pulse is 1.8 mm (the two topics arrive
        # separately, so wait until a pair agrees rather than comparing whatever came last).
        self.assertTrue(wait_for(lambda: abs(self.position.get().data - self.truth.get().data) <= 0.004, 5.0),
                        "encoder %.4f m against truth %.4f m" % (self.position.get().data, self.truth.get().data))

    def test_2_cmd_vel_moves_and_stops_on_timeout(self):
        self.assertTrue(wait_for(lambda: self.position.get() is not None, 20.0))
        before = self.truth.get().data
        end = time.monotonic() + 3.0
        rate = rospy.Rate(20)  # teleop's cadence
        while time.monotonic() < end and not rospy.is_shutdown():
            self.cmd_vel_pub.publish(Twist())  # zero first, then forward
            msg = Twist()
            msg.linear.x = 0.1
            self.cmd_vel_pub.publish(msg)
            rate.sleep()
        moved = self.truth.get().data - before
        self.assertGreater(moved, 0.1, "0.1 m/s for 3 s moved only %.3f m" % moved)
        # Teleop goes quiet: the rover stops and then holds (no drift of more than 3 cm over 2 s).
        window = []

        def still():
            now = time.monotonic()
            window.append((now, self.truth.get().data))
            while window and window[0][0] < now - 2.0:
                window.pop(0)
            values = [p for _, p in window]
            return now - window[0][0] >= 1.9 and max(values) - min(values) <= 0.03

        self.assertTrue(wait_for(still, 15.0), "the rover did not come to rest after cmd_vel stopped")

    def test_3_serial_device_vanishes_and_returns(self):
        self.assertTrue(wait_for(lambda: self.position.get() is not None, 20.0))
        self.rover_levels[:] = []
        count_before = self.position.count
        self.vanish_pub.publish(Float64(3.0))
        self.assertTrue(wait_for(lambda: DiagnosticStatus.ERROR in self.rover_levels, 10.0),
                        "rover diagnostics never reported the lost link")
        # It reconnects by itself and drives again.
        self.assertTrue(wait_for(lambda: self.position.count > count_before + 100, 20.0), "no telemetry after return")
        start = self.position.get().data
        self.assertTrue(self.drive_to(start - 0.3), "rover did not drive after the device came back")

    def test_4_manipulator_targets_and_limits(self):
        self.assertTrue(wait_for(lambda: self.joints.get() is not None, 20.0), "no manipulator/joint_states")
        target = PointStamped()
        target.point.x = 0.2
        target.point.z = 0.6
        self.arm_pub.publish(target)
        # eq. 7: 0.6 m -> round(236.87) = 237 steps -> 0.59968 m; belt: 0.2 m -> 1333 steps -> 0.19995 m.
        expected = (0.19995, (237 - 483.29) / -410.7)

        def there(x, z):
            j = self.joints.get()
            b = self.busy.get()
            return (j is not None and b is not None and not b.data and abs(j.position[0] - x) < 1e-4
                    and abs(j.position[1] - z) < 1e-4)

        self.assertTrue(wait_for(lambda: there(*expected), 20.0), "arm did not reach %s: %s" % (expected, self.joints.get()))
        target.point.x = float("nan")  # leave the horizontal axis
        target.point.z = 0.05          # above the 0.30 m limit: clamped
        self.arm_pub.publish(target)
        self.assertTrue(wait_for(lambda: there(0.19995, (360 - 483.29) / -410.7), 20.0),
                        "arm did not stop at the limit: %s" % self.joints.get())


if __name__ == "__main__":
    rostest.rosrun("cotton_harvester", "control_serial", ControlSerialTest)
