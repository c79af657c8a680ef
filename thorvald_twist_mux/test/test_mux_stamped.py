#!/usr/bin/python3
"""TwistStamped in and out: headers pass through; a plain input gets a stamp and ~frame_id; int timeouts."""
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import TwistStamped

from mux_harness import MuxHarness, twist


class MuxStamped(unittest.TestCase):
    def test_stamped(self):
        h = MuxHarness({'nav': 'nav', 'joy': 'joy_vel'}, {}, out_stamped=True, stamped_inputs=('nav',))
        msg = TwistStamped()
        msg.header.frame_id = 'odom'
        msg.header.stamp = rospy.Time(12, 345)
        msg.header.seq = 7
        msg.twist = twist(1.0)
        h.publish('nav', msg)
        h.wait_output(1.0)
        out = h.outputs[-1][1]
        self.assertEqual(out.header.frame_id, 'odom')
        self.assertEqual(out.header.stamp, rospy.Time(12, 345))

        before = rospy.Time.now()
        sent = time.monotonic()
        h.publish('joy', 2.0)
        h.wait_output(2.0)
        out = h.outputs[-1][1]
        self.assertEqual(out.header.frame_id, 'base_link')
        self.assertGreaterEqual(out.header.stamp, before)

        # Integer timeout 1 [s]: nav stays masked until joy is a second old.
        msg.twist = twist(1.1)
        came_out = h.publish_until_output('nav', msg)
        self.assertGreaterEqual(came_out - sent, 1.0)


if __name__ == '__main__':
    rospy.init_node('test_mux_stamped')
    rostest.rosrun('thorvald_twist_mux', 'mux_stamped', MuxStamped)
