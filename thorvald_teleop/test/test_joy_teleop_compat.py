#!/usr/bin/python3
"""joy_teleop against teleop_twist_joy's parameter forms, with exact expected twists."""
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Joy

from teleop_harness import Recorder, twist_tuple, wait_for

# Per namespace: (axes, buttons, expected (lin x, y, z, ang x, y, z)) in order. None: no message expected.
# Axis values are exact in float32 so products are exact.
CASES = {
    'int_axes': [
        ([0.25, 0.5], [1], (1.0, 0, 0, 0, 0, 0.75)),
        ([0.25], [1], (0.0, 0, 0, 0, 0, 0.75)),  # axis 1 beyond the message reads 0
        ([0.25, 0.5], [], (0, 0, 0, 0, 0, 0)),   # enable beyond the message: released, one stop
        ([0.25, 0.5], [0], None),                # still released: nothing
        ([-0.5, -1.0], [1], (-2.0, 0, 0, 0, 0, -1.5)),
    ],
    'map_axes': [
        ([0.5, 0.25, -0.5, 0.125, 1.0, -1.0], [1], (0.25, -1.0, 0.375, -3.0, 2.0, 0.5)),
    ],
    'turbo': [
        ([0.5, 0.25], [1, 0], (0.25, 0, 0, 0, 0, 0.5)),  # enable: normal scales
        ([0.5, 0.25], [1, 1], (0.5, 0, 0, 0, 0, 2.0)),   # enable + turbo: turbo scales
        ([0.5, 0.25], [0, 1], (0.5, 0, 0, 0, 0, 2.0)),   # turbo alone also drives
        ([0.5, 0.25], [0, 0], (0, 0, 0, 0, 0, 0)),
    ],
    'no_enable': [
        ([0.5, 0.25], [], (0.25, 0, 0, 0, 0, 0.5)),
        ([0.25, 0.5], [], (0.5, 0, 0, 0, 0, 0.25)),
    ],
    'only_turbo': [
        ([0.5, 0.25], [0], (0, 0, 0, 0, 0, 0)),           # no enable button: the first message stops
        ([0.5, 0.25], [1], (0.75, 0, 0, 0, 0, 0.75)),
        ([0.5, 0.25], [0], (0, 0, 0, 0, 0, 0)),
        ([0.5, 0.25], [0], None),
    ],
    # Upstream reads turbo scales only from the scale_*_turbo maps: none given, so turbo sends zero twists.
    'ps3_holonomic': [
        ([0.5, 0.25, -0.75], [0] * 8 + [1, 0, 0], (0, 0, 0, 0, 0, 0)),       # turbo alone
        ([0.5, 0.25, -0.75], [0] * 8 + [1, 0, 1], (0, 0, 0, 0, 0, 0)),       # turbo wins over enable
        ([0.5, 0.25, -0.75], [0] * 10 + [1], (0.1, 0.2, 0, 0, 0, -0.375)),  # enable: normal scales
        ([0.5, 0.25, -0.75], [0] * 8 + [1, 0, 1], (0, 0, 0, 0, 0, 0)),
        ([0.5, 0.25, -0.75], [0] * 11, (0, 0, 0, 0, 0, 0)),                 # released: one stop
        ([0.5, 0.25, -0.75], [0] * 10 + [1], (0.1, 0.2, 0, 0, 0, -0.375)),
    ],
}


class JoyTeleopCompat(unittest.TestCase):
    def run_case(self, ns):
        pub = rospy.Publisher('/%s/joy' % ns, Joy, queue_size=10)
        rec = Recorder('/%s/cmd_vel' % ns, Twist)
        wait_for(lambda: pub.get_num_connections() > 0 and rec.sub.get_num_connections() > 0, 15.0,
                 'connections in %s' % ns)
        self.assertEqual(rec.count(), 0, 'published before the first Joy')
        expected = []
        for axes, buttons, twist in CASES[ns]:
            pub.publish(Joy(axes=axes, buttons=buttons))
            if twist is None:
                continue
            expected.append(twist)
            rec.wait_count(len(expected))
        # A last enabled message proves any message a None case might have produced would have arrived first.
        last_axes, last_buttons, last_twist = next(c for c in reversed(CASES[ns]) if c[2] is not None
                                                   and any(c[2]))
        pub.publish(Joy(axes=last_axes, buttons=last_buttons))
        expected.append(last_twist)
        rec.wait_count(len(expected))
        got = [twist_tuple(m) for m in rec.since(0)]
        self.assertEqual(len(got), len(expected), got)
        for g, e in zip(got, expected):
            for a, b in zip(g, e):
                self.assertAlmostEqual(a, b, places=12, msg='%s: got %s expected %s' % (ns, g, e))

    def test_ps3_holonomic_turbo_without_turbo_scales(self):
        self.run_case('ps3_holonomic')

    def test_cmd_vel_is_latched(self):
        # As in teleop_twist_joy, a subscriber connecting late still gets the last command.
        ns = 'latched'
        pub = rospy.Publisher('/%s/joy' % ns, Joy, queue_size=10)
        early = Recorder('/%s/cmd_vel' % ns, Twist)
        wait_for(lambda: pub.get_num_connections() > 0 and early.sub.get_num_connections() > 0, 15.0,
                 'connections in %s' % ns)
        pub.publish(Joy(axes=[0.25, 0.5], buttons=[1]))
        early.wait_count(1)
        late = Recorder('/%s/cmd_vel' % ns, Twist)
        late.wait_count(1)
        self.assertEqual(late.count(), 1)
        self.assertEqual(twist_tuple(late.last()), twist_tuple(early.last()))
        self.assertEqual(twist_tuple(late.last()), (0.25, 0, 0, 0, 0, 0.125))  # upstream defaults: 0.5 and 0.5

    def test_int_axes(self):
        self.run_case('int_axes')

    def test_map_axes(self):
        self.run_case('map_axes')

    def test_turbo(self):
        self.run_case('turbo')

    def test_no_enable(self):
        self.run_case('no_enable')

    def test_only_turbo(self):
        self.run_case('only_turbo')


if __name__ == '__main__':
    rospy.init_node('test_joy_teleop_compat')
    rostest.rosrun('thorvald_teleop', 'joy_teleop_compat', JoyTeleopCompat)
