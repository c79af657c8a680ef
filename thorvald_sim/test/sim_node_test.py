#!/usr/bin/python3
"""thorvald_sim node test: clock, ground truth, sensors on known geometry, driving through base_driver, and the
pause / step / reset services. Every wait is for a condition with a deadline."""
import math
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import CameraInfo, Image, Imu, LaserScan, PointCloud2, Range
from std_srvs.srv import Empty
from thorvald_sim.srv import Step
from thorvald_testing import Latest, wait_for


class CameraFrames:
    """The simulator's diagnostics count of rendered frames of r1's camera (other nodes publish /diagnostics too)."""

    def __init__(self):
        self.frames = None
        self.stamp = -1.0
        self.sub = rospy.Subscriber("/diagnostics", DiagnosticArray, self.cb, queue_size=20)

    def cb(self, msg):
        for status in msg.status:
            for kv in status.values:
                if kv.key == "r1 camera frames rendered":
                    self.frames = int(kv.value)
                    self.stamp = msg.header.stamp.to_sec()


def yaw(q):
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


class SimNodeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("sim_node_test")
        cls.clock = Latest("/clock", Clock)
        cls.truth = Latest("/r1/ground_truth/odom", Odometry)
        cls.odom = Latest("/r1/odometry/base_raw", Odometry)
        cls.scan = Latest("/r1/scan", LaserScan)
        cls.us = Latest("/r1/ultrasonic/front_left", Range)
        cls.info = Latest("/r1/camera/depth/camera_info", CameraInfo)
        cls.diag = CameraFrames()
        cls.imu = Latest("/r1/imu", Imu)
        cls.cmd = rospy.Publisher("/r1/twist_mux/cmd_vel", Twist, queue_size=1)
        wait_for(lambda: cls.truth.msg is not None and cls.odom.msg is not None, 60.0, "ground truth and odometry")
        wait_for(lambda: cls.clock.msg is not None and cls.clock.msg.clock.to_sec() > 1.0, 30.0, "1 s of sim time")

    def sim_time(self):
        return self.clock.msg.clock.to_sec()

    def test_0_camera_costs_nothing_unwatched(self):
        # The camera is scheduled (its camera_info flows at 5 Hz) but nobody watches its images: nothing rendered.
        wait_for(lambda: self.info.count >= 5, 30.0, "5 camera_info messages")
        stamp = self.clock.msg.clock.to_sec()
        wait_for(lambda: self.diag.stamp > stamp, 30.0, "the simulator's diagnostics after the camera_info messages")
        self.assertEqual(self.diag.frames, 0)
        # Once someone subscribes, frames are rendered.
        cls = type(self)
        cls.cloud = Latest("/r1/camera/depth/points", PointCloud2)
        cls.image = Latest("/r1/camera/color/image_raw", Image)
        wait_for(lambda: self.cloud.msg is not None and self.image.msg is not None, 30.0, "camera images")
        stamp = self.clock.msg.clock.to_sec()
        wait_for(lambda: self.diag.stamp > stamp, 30.0, "the simulator's diagnostics after the images")
        self.assertGreater(self.diag.frames, 0)

    def test_1_sensors_see_known_geometry(self):
        wait_for(lambda: None not in (self.scan.msg, self.us.msg, self.cloud.msg, self.image.msg, self.imu.msg),
                 30.0, "every sensor")
        rear = rospy.get_param("~rear_wall_x")
        start = rospy.get_param("~start_x")
        # Facing -x: the middle beam meets the rear wall's face.
        mid = len(self.scan.msg.ranges) // 2
        self.assertAlmostEqual(self.scan.msg.ranges[mid], (start - rospy.get_param("~lidar_x")) - rear, delta=0.03)
        self.assertEqual(self.scan.msg.header.frame_id, "r1/laser")
        # Down-facing ultrasonic over the headland floor (base_link on the floor at z = 0).
        self.assertAlmostEqual(self.us.msg.range, rospy.get_param("~ultrasonic_z"), delta=0.02)
        self.assertEqual(self.us.msg.radiation_type, Range.ULTRASOUND)
        # Organised cloud of the camera's size in its optical frame; colour image of the same size.
        self.assertEqual((self.cloud.msg.width, self.cloud.msg.height), (80, 60))
        self.assertEqual(self.cloud.msg.header.frame_id, "r1/camera_optical")
        self.assertEqual((self.image.msg.width, self.image.msg.height, self.image.msg.encoding), (80, 60, "rgb8"))
        self.assertAlmostEqual(self.imu.msg.linear_acceleration.z, 9.81, delta=0.3)

    def test_2_drives_and_odometry_agrees(self):
        t0 = self.truth.msg.pose.pose.position
        o0 = self.odom.msg.pose.pose.position
        end = self.sim_time() + 3.0
        while self.sim_time() < end:
            cmd = Twist()
            cmd.linear.x = 0.5
            self.cmd.publish(cmd)
            time.sleep(0.02)  # publishing rate of the command, not synchronisation
        self.cmd.publish(Twist())
        stop = self.sim_time() + 1.5
        wait_for(lambda: self.sim_time() > stop, 20.0, "1.5 s to stop")
        t1 = self.truth.msg.pose.pose.position
        o1 = self.odom.msg.pose.pose.position
        truth_dist = math.hypot(t1.x - t0.x, t1.y - t0.y)
        odom_dist = math.hypot(o1.x - o0.x, o1.y - o0.y)
        # Facing -x, forward means decreasing x; about 0.5 m/s for 3 s minus acceleration and steering.
        self.assertLess(t1.x - t0.x, -1.0)
        self.assertLess(abs(t1.y - t0.y), 0.05)
        # Odometry from joint states and ground truth agree on flat ground within 3 % + 2 cm.
        self.assertAlmostEqual(odom_dist, truth_dist, delta=0.03 * truth_dist + 0.02)
        self.assertAlmostEqual(abs(yaw(self.truth.msg.pose.pose.orientation)), math.pi, delta=0.03)

    def test_3_pause_step_reset(self):
        rospy.wait_for_service("/thorvald_sim/pause", 10.0)
        rospy.ServiceProxy("/thorvald_sim/pause", Empty)()
        step = rospy.ServiceProxy("/thorvald_sim/step", Step)
        before = step(0).time
        res = step(100)
        self.assertTrue(res.success)
        self.assertAlmostEqual(res.time - before, 0.2, delta=1e-6)  # 100 steps of 2 ms
        wait_for(lambda: abs(self.sim_time() - res.time) < 1e-6, 5.0, "clock after stepping")
        rospy.ServiceProxy("/thorvald_sim/unpause", Empty)()
        wait_for(lambda: self.sim_time() > res.time + 0.2, 10.0, "clock to run again")
        self.assertFalse(step(1).success)  # stepping is refused while running
        rospy.ServiceProxy("/thorvald_sim/reset", Empty)()
        after = self.sim_time()
        wait_for(lambda: self.truth.msg.header.stamp.to_sec() > after + 0.05, 10.0, "ground truth after reset")
        p = self.truth.msg.pose.pose.position
        self.assertAlmostEqual(p.x, rospy.get_param("~start_x"), delta=0.02)
        self.assertAlmostEqual(p.y, 0.0, delta=0.02)


if __name__ == "__main__":
    rostest.rosrun("thorvald_sim", "sim_node", SimNodeTest)
