#!/usr/bin/python3
"""A relay board over the virtual bus: base_driver switches io0's output 0 and reads the board's echo back through
can_device_sim; a board that goes silent puts its state in doubt (io/io0/state_unknown latched true, diagnostics
ERROR), and it is known again once the board is back and echoes the command."""
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from std_msgs.msg import Bool

from thorvald_can_devices.srv import InjectFault
from thorvald_testing import wait_for


class RelayBoard(unittest.TestCase):
    def setUp(self):
        self.values = {}
        self.diag = None
        for topic in ("io/io0/state_unknown", "io/io0/out0/state", "io/io1/out1/state"):
            rospy.Subscriber(topic, Bool, lambda m, t=topic: self.values.__setitem__(t, m.data))
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag)
        self.out0 = rospy.Publisher("io/io0/out0", Bool, queue_size=1, latch=True)
        rospy.wait_for_service("can_device_sim/inject_fault", 30.0)
        self.inject = rospy.ServiceProxy("can_device_sim/inject_fault", InjectFault)

    def on_diag(self, msg):
        for s in msg.status:
            if s.name.endswith("io boards"):
                self.diag = s

    def test_switch_read_back_and_lose_the_board(self):
        wait_for(lambda: self.values.get("io/io0/state_unknown") is False, 30.0, "io0 confirmed after start-up")
        wait_for(lambda: self.values.get("io/io1/out1/state") is True, 5.0, "io1 output 1 closed (rl1_init_state)")
        self.assertFalse(self.values.get("io/io0/out0/state"))
        t0 = time.monotonic()
        self.out0.publish(Bool(data=True))
        wait_for(lambda: self.values.get("io/io0/out0/state") is True, 5.0, "io0 output 0 confirmed on")
        rospy.loginfo("relay_board: out0 on confirmed after %.0f ms", 1000.0 * (time.monotonic() - t0))
        wait_for(lambda: self.diag is not None and self.diag.level == DiagnosticStatus.OK, 10.0, "diagnostics OK")

        t0 = time.monotonic()
        self.assertTrue(self.inject("io0", "silent", True).success)
        wait_for(lambda: self.values.get("io/io0/state_unknown") is True, 5.0, "io0 state unknown")
        lost = time.monotonic() - t0
        rospy.loginfo("relay_board: io0 silent -> state unknown after %.0f ms", 1000.0 * lost)
        self.assertLess(lost, 1.0)
        wait_for(lambda: self.diag.level == DiagnosticStatus.ERROR, 10.0, "diagnostics ERROR")
        self.assertIn("relay state unknown: io0", self.diag.message)

        self.assertTrue(self.inject("io0", "silent", False).success)
        wait_for(lambda: self.values.get("io/io0/state_unknown") is False, 10.0, "io0 confirmed again")
        self.assertTrue(self.values.get("io/io0/out0/state"))


if __name__ == "__main__":
    rospy.init_node("relay_board_test")
    rostest.rosrun("thorvald_can_devices", "relay_board", RelayBoard)
