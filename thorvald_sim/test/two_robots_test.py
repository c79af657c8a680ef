#!/usr/bin/python3
"""Two robots in one thorvald_sim world: r1 crabs to its left, r2 gets no command and stays."""
import math
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from thorvald_testing import wait_for


class TwoRobotsTest(unittest.TestCase):
    def test_independent_commands(self):
        rospy.init_node("two_robots_test")
        latest = {}
        subs = [rospy.Subscriber("/%s/ground_truth/odom" % r, Odometry,
                                 lambda m, r=r: latest.__setitem__(r, m)) for r in ("r1", "r2")]
        clock = {}
        rospy.Subscriber("/clock", Clock, lambda m: clock.__setitem__("t", m.clock.to_sec()))
        cmd = rospy.Publisher("/r1/twist_mux/cmd_vel", Twist, queue_size=1)
        wait_for(lambda: len(latest) == 2 and clock.get("t", 0) > 1.0, 60.0, "both robots' ground truth")
        self.assertEqual(latest["r1"].child_frame_id, "r1/base_link")
        self.assertEqual(latest["r2"].child_frame_id, "r2/base_link")
        p1 = latest["r1"].pose.pose.position
        p2 = latest["r2"].pose.pose.position
        self.assertAlmostEqual(p2.y, 4.0, delta=0.02)
        end = clock["t"] + 3.0
        while clock["t"] < end:
            c = Twist()
            c.linear.y = 0.4
            cmd.publish(c)
            time.sleep(0.02)  # command rate, not synchronisation
        cmd.publish(Twist())
        stop = clock["t"] + 1.0
        wait_for(lambda: clock["t"] > stop, 20.0, "1 s to stop")
        q1 = latest["r1"].pose.pose.position
        q2 = latest["r2"].pose.pose.position
        self.assertGreater(q1.y - p1.y, 0.6)  # crabbed left (0.4 m/s for 3 s, minus steering and acceleration)
        self.assertLess(abs(q1.x - p1.x), 0.05)
        self.assertLess(math.hypot(q2.x - p2.x, q2.y - p2.y), 0.005)  # r2 stayed
        del subs


if __name__ == "__main__":
    rostest.rosrun("thorvald_sim", "two_robots", TwoRobotsTest)
