#!/usr/bin/python3
"""A held stick through robot.launch's pad wiring drives the robot for as long as it is held.

The kernel's joystick driver sends an event only when a stick or button changes: a stick held still produces no
events at all. The test writes the pad's initial state and then LB (enable) + left stick fully forward into the
FIFO that the joystick reader treats as /dev/input/js0, writes nothing for HOLD seconds, then releases. Expected
(from the shipped config/xbox.yaml of thorvald_teleop, not from the nodes): forward speed = full deflection
x scale_linear.x (0.5 m/s) x initial gain (0.5) = 0.25 m/s, for the whole hold; a stop after the release.
Synchronisation is on messages with deadlines, never on sleeps.
"""
import errno
import os
import struct
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool, String
from thorvald_testing import wait_for

JS_EVENT_BUTTON, JS_EVENT_AXIS, JS_EVENT_INIT = 0x01, 0x02, 0x80
BUTTONS, AXES = 11, 8          # xpad layout
LB, LEFT_STICK_UP_DOWN = 4, 1  # config/xbox.yaml: enable_button, axis_linear.x
EXPECTED_SPEED = 1.0 * 0.5 * 0.5  # [m/s] full deflection x scale_linear.x x gain
HOLD = 3.0                     # [s] the stick is held this long
SETTLE = 1.0                   # [s] allowed for the base to reach the speed after the press
DEADLINE = 60.0                # [s] for start-up on a loaded 2-core machine


def event(kind, number, value, time_ms=0):
    return struct.pack('<IhBB', time_ms, value, kind, number)


class Series(object):
    """Every message of a topic with its arrival time (monotonic [s])."""

    def __init__(self, topic, cls):
        self.lock = threading.Lock()
        self.items = []
        rospy.Subscriber(topic, cls, self.on_message, queue_size=100)

    def on_message(self, msg):
        with self.lock:
            self.items.append((time.monotonic(), msg))

    def between(self, t0, t1):
        with self.lock:
            return [(t, m) for t, m in self.items if t0 <= t <= t1]

    def last(self):
        with self.lock:
            return self.items[-1] if self.items else None


class RobotPad(unittest.TestCase):
    def setUp(self):
        self.robot = rospy.get_param('~robot')
        self.path = rospy.get_param('~joy_dev')
        self.fd = None
        self.odom = Series('/%s/odometry/base_raw' % self.robot, Odometry)
        self.cmd = Series('/%s/twist_mux/cmd_vel' % self.robot, Twist)
        # Released safety lock, in case the shipped mux config makes it a watchdog.
        self.safety = rospy.Publisher('/%s/safety/lock' % self.robot, Bool, queue_size=1, latch=True)
        self.safety.publish(Bool(data=False))

    def tearDown(self):
        if self.fd is not None:
            os.close(self.fd)
        if os.path.exists(self.path):
            os.unlink(self.path)

    def open_writer(self):
        """Opens the FIFO for writing once the joystick reader has it open (ENXIO until then)."""
        def try_open():
            try:
                self.fd = os.open(self.path, os.O_WRONLY | os.O_NONBLOCK)
                return True
            except OSError as e:
                if e.errno != errno.ENXIO:
                    raise
                return False
        wait_for(try_open, DEADLINE, 'the joystick reader to open %s' % self.path)

    def speed(self):
        last = self.odom.last()
        return None if last is None else last[1].twist.twist.linear.x

    def test_held_stick_drives_continuously(self):
        wait_for(lambda: self.speed() is not None, DEADLINE, 'odometry from base_driver')
        # The fail-safe safety_watchdog lock is released once safety_heartbeat runs.
        locks = Series('/%s/twist_mux/engaged_locks' % self.robot, String)
        wait_for(lambda: locks.last() is not None and locks.last()[1].data == '', DEADLINE,
                 'twist_mux to report no engaged lock')
        os.mkfifo(self.path)
        self.open_writer()
        init = b''.join(event(JS_EVENT_BUTTON | JS_EVENT_INIT, i, 0) for i in range(BUTTONS))
        init += b''.join(event(JS_EVENT_AXIS | JS_EVENT_INIT, i, 0) for i in range(AXES))
        os.write(self.fd, init)
        # Stick up is a negative raw value; the reader inverts it (joy's convention): forward.
        os.write(self.fd, event(JS_EVENT_BUTTON, LB, 1, 10) + event(JS_EVENT_AXIS, LEFT_STICK_UP_DOWN, -32767, 11))
        pressed = time.monotonic()
        wait_for(lambda: time.monotonic() - pressed >= HOLD, HOLD + 1.0, 'the end of the hold')
        released = time.monotonic()
        os.write(self.fd, event(JS_EVENT_AXIS, LEFT_STICK_UP_DOWN, 0, 3011) + event(JS_EVENT_BUTTON, LB, 0, 3012))

        # Continuous motion: from SETTLE after the press to the release, every odometry message reports the
        # commanded speed, and the mux output never falls silent long enough for base_driver's 0.5 s timeout.
        held = self.odom.between(pressed + SETTLE, released)
        self.assertGreater(len(held), 20, 'odometry while the stick was held')
        speeds = [m.twist.twist.linear.x for _, m in held]
        self.assertTrue(all(abs(v - EXPECTED_SPEED) < 0.1 * EXPECTED_SPEED for v in speeds),
                        'speed while held (expected %.3f m/s): min %.3f max %.3f' % (EXPECTED_SPEED, min(speeds),
                                                                                     max(speeds)))
        dx = held[-1][1].pose.pose.position.x - held[0][1].pose.pose.position.x
        span = held[-1][0] - held[0][0]
        self.assertGreater(dx, 0.8 * EXPECTED_SPEED * span, 'distance driven while held: %.3f m in %.2f s' % (dx, span))
        commands = self.cmd.between(pressed, released)
        self.assertGreater(len(commands), 0, 'mux output while held')
        gaps = [b[0] - a[0] for a, b in zip(commands, commands[1:])]
        self.assertLess(max(gaps + [0.0]), 0.25, 'largest gap between mux outputs while held [s]')
        self.assertLess(released - commands[-1][0], 0.25, 'the mux output went silent before the release')
        # The first Joy (all released) may give one stop; from the first forward command on, no stop until release.
        first = next((i for i, (_, m) in enumerate(commands) if m.linear.x > 0.0), None)
        self.assertIsNotNone(first, 'no forward command while held')
        self.assertLess(commands[first][0] - pressed, 0.5, 'the first forward command came late [s]')
        self.assertTrue(all(abs(m.linear.x - EXPECTED_SPEED) < 1e-6 for _, m in commands[first:]),
                        'a command other than %.3f m/s while the stick was held' % EXPECTED_SPEED)

        # Released: the robot stops.
        wait_for(lambda: abs(self.speed()) < 1e-3, 10.0, 'the robot to stop after the release')


if __name__ == '__main__':
    rospy.init_node('robot_pad_test')
    rostest.rosrun('thorvald_bringup', 'robot_pad', RobotPad)
