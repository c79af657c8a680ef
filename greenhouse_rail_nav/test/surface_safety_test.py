#!/usr/bin/python3
"""surface_monitor and bumper as a mission and the mux see them: wheel radius on floor and rail, the safety lock on
an edge under a wheel and on a silent range finder, and the bumper's latched stop that only a reset clears."""
import math
import threading
import time
import unittest

import rospy
import rostest
from sensor_msgs.msg import Range
from std_msgs.msg import Bool
from std_srvs.srv import Trigger
from thorvald_base.srv import SetDriveParams, SetDriveParamsResponse

from thorvald_testing import wait_for

from greenhouse_rail_nav.msg import SurfaceState

FLOOR, RAIL, EDGE = 0.35, 0.295, 0.50
SENSORS = ["front_right", "front_left", "mid_right", "mid_left"]


class SurfaceSafety(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.radius_calls = []
        cls.service = rospy.Service("base_driver/set_drive_params", SetDriveParams, cls.on_set_params)
        cls.ranges = {name: FLOOR for name in SENSORS}
        cls.silent = set()
        cls.pubs = {n: rospy.Publisher("ultrasonic/" + n, Range, queue_size=5) for n in SENSORS}
        cls.lock = None
        cls.bumper_lock = None
        cls.state = None
        rospy.Subscriber("safety/lock", Bool, lambda m: setattr(cls, "lock", m.data))
        rospy.Subscriber("bumper/lock", Bool, lambda m: setattr(cls, "bumper_lock", m.data))
        rospy.Subscriber("surface_monitor/state", SurfaceState, lambda m: setattr(cls, "state", m))
        cls.bumper = rospy.Publisher("bumper", Bool, queue_size=5, latch=True)
        cls.running = True
        cls.thread = threading.Thread(target=cls.publish_ranges, daemon=True)
        cls.thread.start()

    @classmethod
    def tearDownClass(cls):
        cls.running = False

    @classmethod
    def on_set_params(cls, req):
        for p in req.params:
            cls.radius_calls.append((p.drive, p.key, p.value))
        return SetDriveParamsResponse(success=True, message="")

    @classmethod
    def publish_ranges(cls):
        rate = rospy.Rate(20)
        while cls.running and not rospy.is_shutdown():
            for name, pub in cls.pubs.items():
                if name in cls.silent:
                    continue
                m = Range()
                m.header.stamp = rospy.Time.now()
                m.radiation_type = Range.ULTRASOUND
                m.field_of_view, m.min_range, m.max_range = 0.35, 0.02, 2.0
                m.range = cls.ranges[name]
                pub.publish(m)
            rate.sleep()

    def wait_for(self, condition, seconds, what):
        wait_for(condition, seconds, what)

    def set_all(self, value):
        for n in SENSORS:
            self.ranges[n] = value

    def test_1_radius_follows_floor_and_rail(self):
        self.set_all(FLOOR)
        self.wait_for(lambda: ("r_wheel" in [c[1] for c in self.radius_calls]) and self.radius_calls[-1][2] == 0.175,
                      10, "floor wheel radius")
        self.assertEqual(self.radius_calls[-1][0], -1, "the radius applies to every drive")
        self.wait_for(lambda: self.lock is False, 5, "lock released on the floor")
        self.set_all(RAIL)
        self.wait_for(lambda: self.radius_calls[-1][2] == 0.12, 5, "rail wheel radius")
        self.wait_for(lambda: self.state is not None and self.state.wheels == SurfaceState.RAIL
                      and self.state.front == SurfaceState.RAIL, 5, "state: rail under wheels and front")
        self.assertFalse(self.lock)
        # Half on rail, half on floor (a transition): no radius change.
        calls = len(self.radius_calls)
        self.ranges["mid_left"] = FLOOR
        time.sleep(0.5)
        self.assertEqual(len(self.radius_calls), calls)
        self.set_all(FLOOR)
        self.wait_for(lambda: self.radius_calls[-1][2] == 0.175, 5, "floor wheel radius again")

    def test_2_edge_under_a_wheel_locks_at_once(self):
        self.set_all(FLOOR)
        self.wait_for(lambda: self.lock is False, 5, "lock released")
        self.ranges["front_left"] = EDGE  # ahead of the wheels: the mission's business, not a lock
        self.wait_for(lambda: self.state.front == SurfaceState.EDGE, 5, "front edge reported")
        self.assertFalse(self.lock)
        self.ranges["mid_left"] = float("inf")  # REP 117: nothing within range
        self.wait_for(lambda: self.lock is True, 2, "lock on an edge under a wheel")
        self.assertIn("edge under mid_left", self.state.reason)
        self.set_all(FLOOR)
        self.wait_for(lambda: self.lock is False, 5, "lock released when back on the floor")

    def test_3_a_silent_range_finder_locks(self):
        self.set_all(FLOOR)
        self.wait_for(lambda: self.lock is False, 5, "lock released")
        self.silent.add("mid_right")
        self.wait_for(lambda: self.lock is True, 3, "lock on a silent sensor")
        self.assertIn("mid_right silent", self.state.reason)
        self.silent.clear()
        self.wait_for(lambda: self.lock is False, 5, "lock released when it speaks again")

    def test_4_bumper_latches_until_a_person_resets(self):
        reset = rospy.ServiceProxy("bumper/reset", Trigger)
        reset.wait_for_service(10)
        self.wait_for(lambda: self.bumper_lock is False, 5, "bumper released at start")
        self.bumper.publish(Bool(data=True))
        self.wait_for(lambda: self.bumper_lock is True, 2, "bumper lock")
        self.assertFalse(reset().success, "reset must be refused while pressed")
        self.bumper.publish(Bool(data=False))
        time.sleep(0.3)
        self.assertTrue(self.bumper_lock, "the stop must stay latched after release")
        self.assertTrue(reset().success)
        self.wait_for(lambda: self.bumper_lock is False, 2, "bumper lock cleared")


if __name__ == "__main__":
    rospy.init_node("surface_safety_test")
    rostest.rosrun("greenhouse_rail_nav", "surface_safety", SurfaceSafety)
