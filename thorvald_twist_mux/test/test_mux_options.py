#!/usr/bin/python3
"""Opt-in behaviour: one zero twist on timeout or lock, watchdog locks, marker, diagnostics, NaN rejection."""
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticStatus
from std_msgs.msg import Bool
from visualization_msgs.msg import Marker

from mux_harness import Heartbeat, MuxHarness

NAV_TIMEOUT = 0.4  # [s]
HEARTBEAT_TIMEOUT = 0.5  # [s]


class MuxOptions(unittest.TestCase):
    def test_options(self):
        markers = []
        marker_lock = threading.Lock()

        def on_marker(m):
            with marker_lock:
                markers.append(m)

        rospy.Subscriber('twist_mux/marker', Marker, on_marker)
        h = MuxHarness({'teleop': 'teleop', 'nav': 'nav'}, {'safety': 'safety', 'heartbeat': 'heartbeat'})

        # A watchdog lock is engaged until its publisher is heard: nav (10) is masked by it (50), teleop is not.
        h.wait_status('engaged_locks', 'heartbeat')
        h.publish('nav', 1.0)
        h.wait_received('nav')
        beat = Heartbeat(h.pubs['heartbeat'])
        h.wait_status('engaged_locks', '')
        sent = time.monotonic()
        h.publish('nav', 1.1)
        h.wait_output(1.1)
        h.wait_for(lambda: len(markers) >= 1, 5.0, 'a marker')
        with marker_lock:
            m = markers[-1]
        self.assertEqual(m.type, Marker.ARROW)
        self.assertEqual(m.header.frame_id, 'base_link')
        self.assertAlmostEqual(m.points[1].x, 1.1, places=9)

        # nav times out: exactly one zero twist, no earlier than the timeout.
        h.wait_output(0.0)
        self.assertGreaterEqual(h.wait_output(0.0) - sent, NAV_TIMEOUT)
        h.wait_status('active', '')

        def stop_marker_red():
            with marker_lock:
                return bool(markers) and markers[-1].color.r > 0.5

        # The marker follows at the mux's check rate, after the status: wait for it rather than read it at once.
        h.wait_for(stop_marker_red, 5.0, 'a red stop marker')

        # A lock engaging stops the driving input at once.
        h.publish('nav', 1.2)
        h.wait_output(1.2)
        h.publish('safety', Bool(True))
        h.wait_status('engaged_locks', 'safety')
        h.wait_for(lambda: h.output_values()[-1:] == [0.0], 5.0, 'zero after the safety lock')
        h.publish('safety', Bool(False))
        h.wait_status('engaged_locks', '')

        # A takeover by a higher priority is no loss; the zero comes when teleop times out.
        h.publish('nav', 1.3)
        h.wait_output(1.3)
        h.publish('teleop', 2.0)
        h.wait_output(2.0)
        h.wait_for(lambda: h.output_values()[-1:] == [0.0], 5.0, 'zero after teleop timed out')

        # The heartbeat falls silent: its watchdog engages and masks nav, teleop still drives.
        beat.stop()
        h.wait_status('engaged_locks', 'heartbeat')
        self.assertGreaterEqual(time.monotonic() - beat.last, HEARTBEAT_TIMEOUT)
        h.publish('nav', 1.4)
        h.wait_received('nav')
        h.publish('teleop', 2.1)
        h.wait_output(2.1)

        # A non-finite twist is rejected, counted and reported; it does not reach the output.
        h.publish('teleop', float('nan'))
        h.wait_for(lambda: h.diag.get('twist_mux: input teleop', (0,))[0] == DiagnosticStatus.WARN, 5.0,
                   'a warning about the rejected twist')
        self.assertEqual(h.diag['twist_mux: input teleop'][2]['rejected'], '1')
        self.assertEqual(h.diag['twist_mux: lock heartbeat'][0], DiagnosticStatus.WARN)
        h.wait_for(lambda: h.output_values()[-1:] == [0.0], 5.0, 'zero after teleop timed out')

        self.assertEqual(h.output_values(), [1.1, 0.0, 1.2, 0.0, 1.3, 2.0, 0.0, 2.1, 0.0])


if __name__ == '__main__':
    rospy.init_node('test_mux_options')
    rostest.rosrun('thorvald_twist_mux', 'mux_options', MuxOptions)
