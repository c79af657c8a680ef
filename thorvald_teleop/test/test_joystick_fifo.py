#!/usr/bin/python3
"""The joystick node against a FIFO fed the kernel's js_event structs (u32 time [ms], s16 value, u8 type,
u8 number): missing device reported and retried, init events, deadzone scaling, autorepeat, unplug and replug."""
import errno
import os
import struct
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import Joy

from teleop_harness import Recorder, wait_for

JS_EVENT_BUTTON, JS_EVENT_AXIS, JS_EVENT_INIT = 0x01, 0x02, 0x80
DEADZONE = 0.1


def event(kind, number, value, time_ms=0):
    return struct.pack('<IhBB', time_ms, value, kind, number)


def expected_axis(raw):
    """The joy package's convention, computed independently: inverted, dead zone removed and stretched."""
    n = max(-1.0, min(1.0, raw / 32767.0))
    if abs(n) <= DEADZONE:
        return 0.0
    return -(abs(n) - DEADZONE) / (1.0 - DEADZONE) * (1 if n > 0 else -1)


class JoystickFifo(unittest.TestCase):
    def setUp(self):
        self.path = rospy.get_param('/joystick/dev')
        self.status = None
        self.lock = threading.Lock()
        rospy.Subscriber('/diagnostics', DiagnosticArray, self.on_diag)
        self.joy = Recorder('joy', Joy)

    def tearDown(self):
        if os.path.exists(self.path):
            os.unlink(self.path)

    def on_diag(self, msg):
        for s in msg.status:
            if s.name == 'joystick: joystick':
                with self.lock:
                    self.status = (s.level, s.message, {kv.key: kv.value for kv in s.values})

    def get_status(self):
        with self.lock:
            return self.status

    def open_writer(self):
        """Opens the FIFO for writing once the node has it open for reading (ENXIO until then)."""
        fd = []

        def try_open():
            try:
                fd.append(os.open(self.path, os.O_WRONLY | os.O_NONBLOCK))
                return True
            except OSError as e:
                if e.errno != errno.ENXIO:
                    raise
                return False
        wait_for(try_open, 10.0, 'the joystick node to open %s' % self.path)
        return fd[0]

    def wait_joy(self, predicate, what):
        wait_for(lambda: self.joy.last() is not None and predicate(self.joy.last()), 5.0, what)

    def test_fifo_device(self):
        # Missing device: reported as an error and retried; the node stays up.
        wait_for(lambda: self.get_status() is not None and self.get_status()[0] == DiagnosticStatus.ERROR
                 and 'No such file' in self.get_status()[1], 10.0, 'a missing-device error in diagnostics')
        self.assertEqual(self.joy.count(), 0)

        os.mkfifo(self.path)
        fd = self.open_writer()
        init = b''.join(event(JS_EVENT_BUTTON | JS_EVENT_INIT, i, 0) for i in range(4))
        init += b''.join(event(JS_EVENT_AXIS | JS_EVENT_INIT, i, 0) for i in range(2))
        os.write(fd, init)
        self.wait_joy(lambda j: len(j.buttons) == 4 and len(j.axes) == 2, 'the initial state')
        self.assertEqual(list(self.joy.last().buttons), [0, 0, 0, 0])
        self.assertEqual(self.joy.last().header.frame_id, self.path)

        os.write(fd, event(JS_EVENT_BUTTON, 2, 1, 100) + event(JS_EVENT_AXIS, 1, 16384, 101))
        self.wait_joy(lambda j: j.buttons[2] == 1 and j.axes[1] != 0.0, 'button 2 and axis 1')
        self.assertAlmostEqual(self.joy.last().axes[1], expected_axis(16384), places=6)
        self.assertEqual(self.joy.last().axes[0], 0.0)

        os.write(fd, event(JS_EVENT_AXIS, 0, 3000, 102) + event(JS_EVENT_AXIS, 1, -32767, 103))  # 0: in the dead zone
        self.wait_joy(lambda j: j.axes[1] == 1.0, 'axis 1 at full scale')
        self.assertEqual(self.joy.last().axes[0], 0.0)

        # Autorepeat: with no events the state keeps coming at autorepeat_rate.
        n = self.joy.count()
        started = time.monotonic()
        self.joy.wait_count(n + 5, timeout=5.0)
        self.assertGreaterEqual(time.monotonic() - started, 4 * 0.05 * 0.9)  # 5 messages span >= 4 periods
        self.assertTrue(all(list(m.buttons) == [0, 0, 1, 0] for m in self.joy.since(n)))

        # An event of an unknown type is counted, not fatal.
        os.write(fd, event(0x10, 0, 1))
        wait_for(lambda: self.get_status()[2].get('unknown events') == '1', 5.0, 'the unknown event counted')

        # Unplug: the writer leaves; reported, then the node reopens the device when it is back.
        os.close(fd)
        wait_for(lambda: self.get_status()[2].get('disconnections') == '1', 5.0, 'the disconnection')
        fd = self.open_writer()
        os.write(fd, event(JS_EVENT_BUTTON, 3, 1))
        self.wait_joy(lambda j: len(j.buttons) >= 4 and j.buttons[3] == 1, 'button 3 after the replug')
        wait_for(lambda: self.get_status()[0] == DiagnosticStatus.OK and self.get_status()[2]['connections'] == '2',
                 5.0, 'an OK status after the replug')
        os.close(fd)


if __name__ == '__main__':
    rospy.init_node('test_joystick_fifo')
    rostest.rosrun('thorvald_teleop', 'joystick_fifo', JoystickFifo)
