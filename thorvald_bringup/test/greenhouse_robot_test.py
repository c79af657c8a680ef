#!/usr/bin/python3
"""greenhouse_robot.launch on a virtual CAN bus: every node named in ~nodes is up in the robot's namespace, the lamps'
relay board (io0) is confirmed by base_driver over the bus, and uv_interlock holds the relay command off (no mission
light request, not on rails); the mission reports its status."""
import unittest

import rosnode
import rospy
import rostest
from std_msgs.msg import Bool

from thorvald_testing import wait_for


class GreenhouseRobot(unittest.TestCase):
    def setUp(self):
        self.values = {}
        for topic in ("io/io0/state_unknown", "io/io0/out0/state", "io/io0/out0"):
            rospy.Subscriber(topic, Bool, lambda m, t=topic: self.values.__setitem__(t, m.data))

    def test_every_node_comes_up_and_the_relay_board_answers(self):
        ns = rospy.get_namespace()
        wanted = [ns + n for n in rospy.get_param("~nodes")]

        def missing():
            return sorted(set(wanted) - set(rosnode.get_node_names()))

        wait_for(lambda: not missing(), 60.0, "every node up")
        wait_for(lambda: self.values.get("io/io0/state_unknown") is False, 30.0, "io0 confirmed over the bus")
        wait_for(lambda: self.values.get("io/io0/out0") is False, 10.0, "the interlock's relay command off")
        self.assertFalse(self.values.get("io/io0/out0/state"))
        rospy.loginfo("greenhouse_robot: %d nodes up, relay board confirmed, lamps' relay off", len(wanted))
        self.assertEqual(missing(), [])


if __name__ == "__main__":
    rospy.init_node("greenhouse_robot_test")
    rostest.rosrun("thorvald_bringup", "greenhouse_robot", GreenhouseRobot)
