#!/usr/bin/python3
"""SimHardware's relay board through base_driver: confirmed, switched with its echo and truth, then silent: the
state goes unknown within the silence timeout and the diagnostics say why."""
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from std_msgs.msg import Bool, UInt8
from thorvald_testing import Latest, wait_for


def io_status(diagnostics):
    for s in diagnostics.msg.status if diagnostics.msg else []:
        if s.name.endswith("io boards"):
            return s
    return None


class SimIoBoardTest(unittest.TestCase):
    def test_silent_board_puts_the_relay_state_in_doubt(self):
        rospy.init_node("sim_io_board_test")
        unknown = Latest("/r1/io/io0/state_unknown", Bool)
        state = Latest("/r1/io/io0/out0/state", Bool)
        truth = Latest("/r1/sim/io/io0", UInt8)
        diagnostics = Latest("/diagnostics", DiagnosticArray)
        out0 = rospy.Publisher("/r1/io/io0/out0", Bool, queue_size=1, latch=True)
        wait_for(lambda: unknown.msg is not None and not unknown.msg.data, 30.0, "io0 confirmed")
        wait_for(lambda: None not in (truth.msg, state.msg), 5.0, "the relay's truth and confirmed state")
        self.assertEqual(truth.msg.data, 0)
        self.assertFalse(state.msg.data)
        out0.publish(Bool(data=True))
        wait_for(lambda: state.msg.data, 5.0, "out0 confirmed on")
        self.assertEqual(truth.msg.data, 1)  # the relay switched before its echo was confirmed
        wait_for(lambda: unknown.msg.data, 10.0, "io0 silent: state unknown")
        self.assertEqual(truth.msg.data, 0)  # unpowered: the relays dropped out
        self.assertTrue(state.msg.data)  # the last confirmed state stays, in doubt
        wait_for(lambda: io_status(diagnostics) is not None and io_status(diagnostics).level == DiagnosticStatus.ERROR,
                 5.0, "'io boards' diagnostics in error")
        status = io_status(diagnostics)
        self.assertIn("relay state unknown: io0: board silent for", status.message)
        values = {v.key: v.value for v in status.values}
        self.assertEqual(values.get("io0 answering"), "no")
        self.assertEqual(values.get("io0 outputs confirmed"), "unknown")


if __name__ == "__main__":
    rostest.rosrun("thorvald_sim", "sim_io_board", SimIoBoardTest)
