#!/usr/bin/python3
"""odom_fusion (odom_fusion.test): wheel odometry whose yaw rate is biased plus a gyro that reads the truth (driving
straight); the fused odometry must keep the heading. A configuration asking for what is not supported must stop
the node with a clear error."""
import math
import subprocess
import sys
import time
import unittest

import rospy
import rostest
import roslib.packages
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu


class OdomFusionTest(unittest.TestCase):
    def test_gyro_keeps_the_heading_of_biased_wheel_odometry(self):
        odom_pub = rospy.Publisher("base_driver/odometry/base_raw", Odometry, queue_size=10)
        imu_pub = rospy.Publisher("imu/data", Imu, queue_size=10)
        latest = {}
        rospy.Subscriber("odometry/filtered", Odometry, lambda m: latest.update(msg=m))
        deadline = time.time() + 20.0
        while odom_pub.get_num_connections() == 0 or imu_pub.get_num_connections() == 0:
            self.assertLess(time.time(), deadline, "odom_fusion did not subscribe")
            time.sleep(0.05)
        start = time.time()
        while time.time() - start < 5.0:  # 5 s at 50 Hz: 0.5 m/s straight, wheels claim 0.05 rad/s of turning
            now = rospy.Time.now()
            o = Odometry()
            o.header.stamp = now
            o.twist.twist.linear.x = 0.5
            o.twist.twist.angular.z = 0.05
            o.twist.covariance[0] = o.twist.covariance[7] = 1e-4
            o.twist.covariance[35] = 1e-2
            odom_pub.publish(o)
            i = Imu()
            i.header.stamp = now
            i.orientation_covariance[0] = -1.0  # no orientation
            i.angular_velocity.z = 0.0
            i.angular_velocity_covariance[8] = 1e-5
            imu_pub.publish(i)
            time.sleep(0.02)
        time.sleep(0.2)
        self.assertIn("msg", latest)
        m = latest["msg"]
        q = m.pose.pose.orientation
        yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
        self.assertLess(abs(yaw), 0.1 * 0.05 * 5.0, "fused yaw %f" % yaw)  # wheels alone: 0.25 rad
        self.assertGreater(m.pose.pose.position.x, 2.0)
        self.assertEqual(m.header.frame_id, "odom")
        self.assertEqual(m.child_frame_id, "base_link")

    def test_unsupported_configuration_stops_the_node_with_the_reason(self):
        exe = roslib.packages.find_node("thorvald_navigation", "odom_fusion")[0]
        cfg = [False] * 15
        cfg[6] = cfg[11] = cfg[12] = True  # vx, vyaw and ax: acceleration is not supported
        rospy.set_param("/odom_fusion_bad/odom0_config", cfg)  # lists cannot be given as _name:= arguments
        p = subprocess.run([exe, "__name:=odom_fusion_bad", "_odom0:=odom"], capture_output=True, text=True, timeout=30)
        self.assertEqual(p.returncode, 1)
        self.assertIn("ax", p.stdout + p.stderr)
        p = subprocess.run([exe, "__name:=odom_fusion_bad2", "_odom0:=odom", "_odom1:=other"],
                           capture_output=True, text=True, timeout=30)
        self.assertEqual(p.returncode, 1)
        self.assertIn("odom1", p.stdout + p.stderr)
        # The wheels' yaw rate left out and no IMU: nothing would turn the heading.
        cfg = [False] * 15
        cfg[6] = cfg[7] = True
        rospy.set_param("/odom_fusion_bad3/odom0_config", cfg)
        p = subprocess.run([exe, "__name:=odom_fusion_bad3", "_odom0:=odom"],
                           capture_output=True, text=True, timeout=30)
        self.assertEqual(p.returncode, 1)
        self.assertIn("nothing gives the heading", p.stdout + p.stderr)


if __name__ == "__main__":
    rospy.init_node("odom_fusion_node_test")
    rostest.rosrun("thorvald_navigation", "odom_fusion_node", OdomFusionTest, sys.argv)
