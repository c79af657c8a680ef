#!/usr/bin/python3
"""joy_teleop with config/xbox.yaml: the Thorvald drive modes, gain steps, turbo, priority lock, deadman and the
steering homing call (absent service reported, present service called)."""
import threading
import time
import unittest

import rospy
import rostest
import yaml
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import Twist
from rospkg import RosPack
from sensor_msgs.msg import Joy
from std_msgs.msg import Bool
from std_srvs.srv import Trigger, TriggerResponse

from teleop_harness import Recorder, twist_tuple, wait_for

PAD = yaml.safe_load(open(RosPack().get_path('thorvald_teleop') + '/config/xbox.yaml'))
A, B, X, Y, LB, RB, BACK, START, LSTICK = 0, 1, 2, 3, 4, 5, 6, 7, 9
STICKS = [0.25, 0.5, 0.0, -0.75]  # lateral (axis 0), forward (axis 1), -, yaw (axis 3); exact in float32


def buttons(*down):
    b = [0] * 11
    for i in down:
        b[i] = 1
    return b


class JoyTeleopThorvald(unittest.TestCase):
    def setUp(self):
        self.joy = rospy.Publisher('joy', Joy, queue_size=10)
        self.cmd = Recorder('teleop_joy/cmd_vel', Twist)
        self.lock = Recorder('teleop_joy/joy_priority', Bool)
        self.diag = {}
        self.diag_lock = threading.Lock()
        rospy.Subscriber('/diagnostics', DiagnosticArray, self.on_diag)
        wait_for(lambda: self.joy.get_num_connections() > 0 and self.cmd.sub.get_num_connections() > 0, 15.0,
                 'connections to joy_teleop')

    def on_diag(self, msg):
        with self.diag_lock:
            for s in msg.status:
                if s.name == 'joy_teleop: teleop':
                    self.diag = {kv.key: kv.value for kv in s.values}

    def send(self, *down, axes=STICKS):
        """Publishes one Joy and returns the command it produced."""
        n = self.cmd.count()
        self.joy.publish(Joy(axes=axes, buttons=buttons(*down)))
        self.cmd.wait_count(n + 1)
        return twist_tuple(self.cmd.last())

    def expect(self, got, lin_x, lin_y, ang_z):
        for g, e in zip(got, (lin_x, lin_y, 0.0, 0.0, 0.0, ang_z)):
            self.assertAlmostEqual(g, e, places=9, msg='got %s' % (got,))

    def test_modes_gain_turbo_priority_deadman_homing(self):
        gain = PAD['gain']
        sx, sy, syaw = PAD['scale_linear']['x'], PAD['scale_linear']['y'], PAD['scale_angular']['yaw']
        fwd, lat, yaw = STICKS[1], STICKS[0], STICKS[3]
        self.assertEqual(PAD['initial_mode'], 'drive')
        # Drive mode (initial): forward and yaw, no crab.
        self.expect(self.send(LB), fwd * sx * gain, 0.0, yaw * syaw * gain)
        # X: omni adds the lateral speed.
        self.expect(self.send(LB, X), fwd * sx * gain, lat * sy * gain, yaw * syaw * gain)
        # B: turn in place.
        self.expect(self.send(LB, B), 0.0, 0.0, yaw * syaw * gain)
        # Start / Back step the gain by gain_step, once per press.
        step = PAD['gain_step']
        self.expect(self.send(LB, START), 0.0, 0.0, yaw * syaw * (gain + step))
        self.expect(self.send(LB, START), 0.0, 0.0, yaw * syaw * (gain + step))  # held: no second step
        self.send(LB)
        self.expect(self.send(LB, BACK), 0.0, 0.0, yaw * syaw * gain)
        # A: back to drive; RB alone: turbo scales.
        self.send(LB, A)
        self.expect(self.send(RB), fwd * PAD['scale_linear_turbo']['x'] * gain, 0.0,
                    yaw * PAD['scale_angular_turbo']['yaw'] * gain)
        # Released: exactly one stop.
        self.expect(self.send(), 0.0, 0.0, 0.0)
        n = self.cmd.count()
        self.joy.publish(Joy(axes=STICKS, buttons=buttons()))

        # Y toggles the priority lock (latched Bool).
        self.joy.publish(Joy(axes=STICKS, buttons=buttons(Y)))
        self.lock.wait_count(1)
        self.assertTrue(self.lock.last().data)
        self.joy.publish(Joy(axes=STICKS, buttons=buttons()))
        self.joy.publish(Joy(axes=STICKS, buttons=buttons(Y)))
        self.lock.wait_count(2)
        self.assertFalse(self.lock.last().data)
        self.assertEqual(self.cmd.count(), n, 'released pad published again')

        # Deadman: the pad falls silent while driving; one stop, no earlier than joy_timeout.
        silent_from = time.monotonic()  # before the last message: joy_teleop hears it later
        self.send(LB)
        self.cmd.wait_count(self.cmd.count() + 1, timeout=5.0)
        self.assertGreaterEqual(time.monotonic() - silent_from, PAD['joy_timeout'])
        self.expect(twist_tuple(self.cmd.last()), 0.0, 0.0, 0.0)

        # Homing without a base_driver: reported, nothing crashes.
        self.joy.publish(Joy(axes=STICKS, buttons=buttons(LB)))
        self.joy.publish(Joy(axes=STICKS, buttons=buttons(LB, LSTICK)))
        wait_for(lambda: 'not available' in self.diag.get('steering homing last result', ''), 10.0,
                 'homing reported as unavailable')
        # With the service: called once per press (while LB is held).
        calls = []
        rospy.Service('base_driver/home_steering', Trigger,
                      lambda req: calls.append(1) or TriggerResponse(success=True, message='homed'))
        rospy.wait_for_service('base_driver/home_steering', timeout=10.0)  # rospy registers asynchronously
        self.joy.publish(Joy(axes=STICKS, buttons=buttons(LB)))
        self.joy.publish(Joy(axes=STICKS, buttons=buttons(LB, LSTICK)))
        wait_for(lambda: 'done: homed' in self.diag.get('steering homing last result', ''), 10.0, 'homing done')
        self.assertEqual(len(calls), 1)
        self.assertEqual(self.diag['steering homing requests'], '2')


if __name__ == '__main__':
    rospy.init_node('test_joy_teleop_thorvald')
    rostest.rosrun('thorvald_teleop', 'joy_teleop_thorvald', JoyTeleopThorvald)
