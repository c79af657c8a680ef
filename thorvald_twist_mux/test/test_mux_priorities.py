#!/usr/bin/python3
"""twist_mux priorities, first-listed ties, timeouts, timeout 0 and the absence of unsolicited output."""
import time
import unittest

import rospy
import rostest

from mux_harness import MuxHarness

TIMEOUT = 0.5  # [s] of high, low and tie in mux_priorities.test


class MuxPriorities(unittest.TestCase):
    def test_priorities_ties_timeouts(self):
        h = MuxHarness({'high': 'high', 'low': 'low', 'tie': 'tie', 'forever': 'forever'}, {})
        h.wait_status('active', '')
        self.assertEqual(h.output_values(), [], 'published before any input')

        forever_sent = time.monotonic()
        h.publish('forever', 5.0)  # lowest priority, timeout 0: wins now, and keeps competing for ever
        h.wait_output(5.0)
        h.publish('low', 1.0)
        h.wait_output(1.0)
        h.publish('high', 2.0)
        h.wait_output(2.0)
        h.publish('low', 1.1)  # outranked by high
        h.publish('tie', 3.0)  # same priority as high, listed later: high keeps it
        h.wait_received('low')
        h.wait_received('tie')
        last_high = time.monotonic()  # before publishing: the mux stamps the message later
        h.publish('high', 2.1)
        h.wait_output(2.1)

        # high times out: tie takes over no earlier than TIMEOUT after high's last message.
        tie_out = h.publish_until_output('tie', 3.1)
        self.assertGreaterEqual(tie_out - last_high, TIMEOUT)
        # Back on high: tie has the same priority but high is listed first.
        h.publish('high', 2.2)
        h.wait_output(2.2)
        h.publish('tie', 3.2)
        h.wait_received('tie')

        # Everything with a timeout expires; forever (timeout 0, heard seconds ago) is active again.
        h.wait_status('active', 'forever')
        self.assertGreater(time.monotonic() - forever_sent, 2 * TIMEOUT)
        h.publish('low', 1.2)  # low outranks forever again
        h.wait_output(1.2)

        # Each accepted message came out exactly once, in order, and nothing else did.
        values = h.output_values()
        expected = [5.0, 1.0, 2.0, 2.1]
        self.assertEqual(values[:4], expected)
        # tie 3.1 may have been sent several times before high's timeout; only the copies after it came out.
        rest = values[4:]
        self.assertEqual([v for v in rest if v != 3.1], [2.2, 1.2])
        self.assertTrue(all(v in (3.1, 2.2, 1.2) for v in rest))
        self.assertEqual(rest.index(2.2), rest.count(3.1))


if __name__ == '__main__':
    rospy.init_node('test_mux_priorities')
    rostest.rosrun('thorvald_twist_mux', 'mux_priorities', MuxPriorities)
