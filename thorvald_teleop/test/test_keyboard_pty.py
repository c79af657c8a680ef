#!/usr/bin/python3
"""keyboard_teleop on a pseudo-terminal: help screen, arrows and letters, speed steps, stop, key timeout, quit with
a final stop, and a stop on SIGTERM."""
import signal
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from roslib.packages import find_node

from teleop_harness import Recorder, twist_tuple, wait_for
from thorvald_testing import PtyProcess

LINEAR_MAX, ANGULAR_MAX, GAIN = 1.0, 2.0, 0.5


class Terminal(PtyProcess):
    """keyboard_teleop with a pty as its controlling stdin/stdout; collects what it prints."""

    def __init__(self, name, key_timeout):
        exe = find_node('thorvald_teleop', 'keyboard_teleop')[0]
        super().__init__(
            [exe, '__name:=%s' % name, 'cmd_vel:=/%s/cmd_vel' % name, '_linear_speed_max:=%f' % LINEAR_MAX,
             '_angular_speed_max:=%f' % ANGULAR_MAX, '_gain:=%f' % GAIN, '_key_timeout:=%f' % key_timeout,
             '_repeat_rate:=10.0'], stderr_to_pty=False)

    def type(self, keys):
        self.write(keys)


class KeyboardPty(unittest.TestCase):
    def expect(self, rec, lin_x, lin_y, ang_z):
        wait_for(lambda: rec.last() is not None and all(
            abs(g - e) < 1e-9 for g, e in zip(twist_tuple(rec.last()), (lin_x, lin_y, 0, 0, 0, ang_z)))
            , 5.0, 'twist %s' % ((lin_x, lin_y, ang_z),))

    def test_keys_latched(self):
        rec = Recorder('/kb_latched/cmd_vel', Twist)
        term = Terminal('kb_latched', key_timeout=0.0)
        try:
            wait_for(lambda: 'Thorvald keyboard teleop' in term.text() and rec.sub.get_num_connections() > 0, 15.0,
                     'the help screen and a connection')
            self.assertIn('w / Up', term.text())
            self.assertIn('Ctrl-C', term.text())
            self.assertEqual(rec.count(), 0, 'published before any key')
            v, w = LINEAR_MAX * GAIN, ANGULAR_MAX * GAIN
            term.type(b'w')
            self.expect(rec, v, 0, 0)
            term.type(b'\x1b[D')  # left arrow: turn left
            self.expect(rec, 0, 0, w)
            term.type(b'\x1b[C')  # right arrow
            self.expect(rec, 0, 0, -w)
            term.type(b'+')  # gain 0.6 keeps turning, faster
            self.expect(rec, 0, 0, -ANGULAR_MAX * 0.6)
            self.assertIn('speed: 0.60 m/s', term.text())
            term.type(b'e')  # crab right
            self.expect(rec, 0, -LINEAR_MAX * 0.6, 0)
            term.type(b'-\x1b[B')  # slower, backward
            self.expect(rec, -v, 0, 0)
            # Latched (key_timeout 0): the command is repeated until space.
            n = rec.count()
            rec.wait_count(n + 3)
            self.assertTrue(all(abs(m.linear.x + v) < 1e-9 for m in rec.since(n)))
            term.type(b' ')
            self.expect(rec, 0, 0, 0)
            term.type(b'h')
            wait_for(lambda: term.text().count('Thorvald keyboard teleop') == 2, 5.0, 'the help again')
            term.type(b's')
            self.expect(rec, -v, 0, 0)
            term.type(b'\x03')  # Ctrl-C in raw mode: stop and quit
            self.assertEqual(term.proc.wait(timeout=10), 0)
            self.expect(rec, 0, 0, 0)
            self.assertIn('stopped', term.text())
        finally:
            term.close()

    def test_key_timeout_and_sigterm(self):
        rec = Recorder('/kb_timeout/cmd_vel', Twist)
        term = Terminal('kb_timeout', key_timeout=0.3)
        try:
            wait_for(lambda: 'Thorvald keyboard teleop' in term.text() and rec.sub.get_num_connections() > 0, 15.0,
                     'the help screen and a connection')
            self.assertIn('stops 0.3 s after the last key', term.text())
            typed = time.monotonic()
            term.type(b'a')
            self.expect(rec, 0, 0, ANGULAR_MAX * GAIN)
            self.expect(rec, 0, 0, 0)  # no key for 0.3 s: stop
            self.assertGreaterEqual(time.monotonic() - typed, 0.3)
            n = rec.count()
            term.type(b'w')
            self.expect(rec, LINEAR_MAX * GAIN, 0, 0)
            term.proc.send_signal(signal.SIGTERM)
            self.assertEqual(term.proc.wait(timeout=10), 0)
            self.expect(rec, 0, 0, 0)
            self.assertGreater(rec.count(), n)
        finally:
            term.close()


if __name__ == '__main__':
    rospy.init_node('test_keyboard_pty')
    rostest.rosrun('thorvald_teleop', 'keyboard_pty', KeyboardPty)
