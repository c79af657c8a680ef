#!/usr/bin/python3
"""uv_interlock as the robot sees it: with every input permitting the lamps' relay goes on; each input that stops
permitting switches it off within 100 ms (measured from the message going out to the relay command coming back, wall
clock), and an input that goes silent switches it off once its timeout has passed."""
import threading
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool

from thorvald_base.msg import BaseState
from thorvald_testing import wait_for

from greenhouse_rail_nav.msg import SurfaceState

LIMIT_S = 0.1  # lamps off within 100 ms of any input


class Inputs:
    """Every input of the interlock, republished at 50 Hz like the robot's nodes do."""

    def __init__(self):
        self.permit = {n: True for n in ("rails", "speed", "detected", "present", "base", "safety", "bumper")}
        self.silent = set()
        self.pubs = {
            "rails": rospy.Publisher("surface_monitor/state", SurfaceState, queue_size=5, tcp_nodelay=True),
            "speed": rospy.Publisher("odometry/base_raw", Odometry, queue_size=5, tcp_nodelay=True),
            "detected": rospy.Publisher("people_detected", Bool, queue_size=5, tcp_nodelay=True),
            "present": rospy.Publisher("people_present", Bool, queue_size=5, tcp_nodelay=True),
            "base": rospy.Publisher("base_state", BaseState, queue_size=5, tcp_nodelay=True),
            "safety": rospy.Publisher("safety/lock", Bool, queue_size=5, tcp_nodelay=True),
            "bumper": rospy.Publisher("bumper/lock", Bool, queue_size=5, tcp_nodelay=True),
        }
        self.request = rospy.Publisher("uv_lights", Bool, queue_size=1, latch=True, tcp_nodelay=True)
        self.lock = threading.Lock()

    def message(self, name):
        ok = self.permit[name]
        if name == "rails":
            m = SurfaceState()
            m.wheels = SurfaceState.RAIL if ok else SurfaceState.FLOOR
            return m
        if name == "speed":
            m = Odometry()
            m.twist.twist.linear.x = 0.5 if ok else 0.2
            return m
        if name == "base":
            m = BaseState()
            m.safety_stop = not ok
            return m
        return Bool(data=not ok)  # people_detected, people_present and the locks permit when false

    def send(self, name):
        with self.lock:
            if name not in self.silent:
                self.pubs[name].publish(self.message(name))

    def loop(self):
        rate = rospy.Rate(50)
        while not rospy.is_shutdown():
            for name in self.pubs:
                self.send(name)
            rate.sleep()


class UvInterlock(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.relay = []  # (monotonic time, value)
        rospy.Subscriber("uv_relay", Bool, lambda m: cls.relay.append((time.monotonic(), m.data)), tcp_nodelay=True)
        cls.inputs = Inputs()
        threading.Thread(target=cls.inputs.loop, daemon=True).start()
        wait_for(lambda: cls.inputs.request.get_num_connections() > 0, 10.0, "uv_interlock subscribed to uv_lights")
        cls.latencies = {}

    def relay_on(self):
        return bool(self.relay) and self.relay[-1][1]

    def all_permit(self):
        with self.inputs.lock:
            self.inputs.silent.clear()
            for name in self.inputs.permit:
                self.inputs.permit[name] = True
        self.inputs.request.publish(Bool(data=True))
        wait_for(self.relay_on, 5.0, "relay on with every input permitting")

    def time_off(self, act):
        """Runs act() and returns the seconds until the relay command is off."""
        count = len(self.relay)
        t0 = time.monotonic()
        act()
        wait_for(lambda: any(not v for _, v in self.relay[count:]), 5.0, "relay off")
        return next(t for t, v in self.relay[count:] if not v) - t0

    def test_each_input_forces_the_lamps_off(self):
        for name in ("rails", "speed", "detected", "present", "base", "safety", "bumper", "request"):
            self.all_permit()
            time.sleep(0.1)  # a few cycles of every input at rest

            def flip():
                if name == "request":
                    self.inputs.request.publish(Bool(data=False))
                    return
                with self.inputs.lock:
                    self.inputs.permit[name] = False
                self.inputs.send(name)

            latency = self.time_off(flip)
            self.latencies[name] = latency
            rospy.loginfo("uv_interlock: %s -> relay off in %.1f ms", name, 1000.0 * latency)
            self.assertLess(latency, LIMIT_S, name)
        print("RESULT uv_interlock_off_latency_ms max %.1f (%s)" % (
            1000.0 * max(self.latencies.values()),
            ", ".join("%s %.1f" % (k, 1000.0 * v) for k, v in self.latencies.items())))

    def test_silent_input_forces_the_lamps_off_after_its_timeout(self):
        self.all_permit()
        time.sleep(0.1)

        def silence():
            with self.inputs.lock:
                self.inputs.silent.add("rails")

        latency = self.time_off(silence)
        rospy.loginfo("uv_interlock: on_rails silent -> relay off after %.1f ms (timeout 300 ms)", 1000.0 * latency)
        self.assertGreater(latency, 0.3 - 0.03)  # last message up to one period (20 ms) before the silence
        self.assertLess(latency, 0.3 + LIMIT_S)


if __name__ == "__main__":
    rospy.init_node("uv_interlock_test")
    rostest.rosrun("greenhouse_rail_nav", "uv_interlock", UvInterlock)
