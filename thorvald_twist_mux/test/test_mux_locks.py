#!/usr/bin/python3
"""Locks of the shipped configuration: joy_priority masks navigation only, safety masks everything."""
import unittest

import rospy
import rostest
from std_msgs.msg import Bool

from mux_harness import MuxHarness


class MuxLocks(unittest.TestCase):
    def test_locks(self):
        h = MuxHarness({'teleop': 'teleop_joy/cmd_vel', 'navigation': 'nav_vel'},
                       {'safety': 'safety/lock', 'joy_priority': 'teleop_joy/joy_priority'},
                       out_topic='twist_mux/cmd_vel')
        h.wait_status('engaged_locks', '')
        h.publish('navigation', 1.0)
        h.wait_output(1.0)

        # The pad's priority lock (50) masks navigation (10), not teleop (100).
        h.publish('joy_priority', Bool(True))
        h.wait_status('engaged_locks', 'joy_priority')
        h.wait_status('active', '')
        h.publish('navigation', 1.1)
        h.wait_received('navigation')
        h.publish('teleop', 2.0)
        h.wait_output(2.0)
        h.publish('joy_priority', Bool(False))
        h.wait_status('engaged_locks', '')
        h.publish_until_output('navigation', 1.2)  # once teleop has timed out

        # The safety lock (255) masks every input; a false releases it.
        h.publish('safety', Bool(True))
        h.wait_status('engaged_locks', 'safety')
        h.publish('teleop', 2.1)
        h.publish('navigation', 1.3)
        h.wait_received('teleop')
        h.wait_received('navigation')
        h.publish('safety', Bool(False))
        h.wait_status('engaged_locks', '')
        h.publish('teleop', 2.2)
        h.wait_output(2.2)

        # Both locks at once: released only when both are.
        h.publish('safety', Bool(True))
        h.publish('joy_priority', Bool(True))
        h.wait_status('engaged_locks', 'safety,joy_priority')
        h.publish('safety', Bool(False))
        h.wait_status('engaged_locks', 'joy_priority')
        h.publish('teleop', 2.3)
        h.wait_output(2.3)

        values = h.output_values()
        self.assertEqual(values[:2], [1.0, 2.0])
        self.assertEqual([v for v in values[2:] if v != 1.2], [2.2, 2.3])
        self.assertNotIn(1.1, values)
        self.assertNotIn(1.3, values)
        self.assertNotIn(2.1, values)


if __name__ == '__main__':
    rospy.init_node('test_mux_locks')
    rostest.rosrun('thorvald_twist_mux', 'mux_locks', MuxLocks)
