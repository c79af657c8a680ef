#!/usr/bin/python3
"""sim.launch end to end: a twist on nav_vel goes through the mux to base_driver, MuJoCo moves the robot, and
base_driver's odometry agrees with the simulator's ground truth."""
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry


class SimLaunch(unittest.TestCase):
    def setUp(self):
        self.truth = None
        self.odom = None
        rospy.Subscriber("/thorvald_001/ground_truth/odom", Odometry, lambda m: setattr(self, "truth", m))
        rospy.Subscriber("/thorvald_001/odometry/base_raw", Odometry, lambda m: setattr(self, "odom", m))
        self.cmd = rospy.Publisher("/thorvald_001/nav_vel", Twist, queue_size=1)

    def wait_for(self, condition, wall_s):
        end = time.monotonic() + wall_s
        while time.monotonic() < end and not rospy.is_shutdown():
            if condition():
                return True
            time.sleep(0.01)
        return False

    def test_drive_straight_through_nav_vel(self):
        self.assertTrue(self.wait_for(lambda: self.truth is not None and self.odom is not None, 60),
                        "no ground truth or odometry")
        self.assertTrue(self.wait_for(lambda: self.cmd.get_num_connections() > 0, 20), "twist_mux not listening")
        x0_truth = self.truth.pose.pose.position.x
        x0_odom = self.odom.pose.pose.position.x
        forward = Twist()
        forward.linear.x = 0.3
        # Drive until ground truth has moved 1 m (publishing at 10 Hz of wall time, the mux's timeout is 0.5 s).
        end = time.monotonic() + 60
        while time.monotonic() < end and self.truth.pose.pose.position.x - x0_truth < 1.0:
            self.cmd.publish(forward)
            time.sleep(0.1)
        self.cmd.publish(Twist())
        self.assertTrue(self.wait_for(lambda: abs(self.truth.twist.twist.linear.x) < 0.01, 30), "never stopped")
        moved_truth = self.truth.pose.pose.position.x - x0_truth
        moved_odom = self.odom.pose.pose.position.x - x0_odom
        self.assertGreater(moved_truth, 0.95)
        # Flat ground, no slip: odometry within 3 cm + 2 % of the truth.
        self.assertLess(abs(moved_odom - moved_truth), 0.03 + 0.02 * moved_truth)
        self.assertLess(abs(self.truth.pose.pose.position.y), 0.05)


if __name__ == "__main__":
    rospy.init_node("sim_launch_test")
    rostest.rosrun("thorvald_bringup", "sim_launch", SimLaunch)
