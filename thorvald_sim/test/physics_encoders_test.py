#!/usr/bin/python3
"""Encoders from the physics through base_driver and the SimHardware plugin: driving into the greenhouse's rear
wall, the wheels stall in joint_states and odometry stops growing while the command keeps asking for speed.
Every wait is for a condition in simulated time with a wall-clock deadline."""
import math
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState
from thorvald_testing import Latest, wait_for


class PhysicsEncodersTest(unittest.TestCase):
    def test_wheels_stall_at_the_wall(self):
        rospy.init_node("physics_encoders_test")
        clock = Latest("/clock", Clock)
        truth = Latest("/r1/ground_truth/odom", Odometry)
        odom = Latest("/r1/odometry/base_raw", Odometry)
        joints = Latest("/r1/joint_states", JointState)
        cmd_pub = rospy.Publisher("/r1/twist_mux/cmd_vel", Twist, queue_size=1)
        wait_for(lambda: None not in (clock.msg, truth.msg, odom.msg, joints.msg), 90.0, "simulator and base_driver")
        now = lambda: clock.msg.clock.to_sec()
        speed = rospy.get_param("~speed")
        stop = threading.Event()

        def command():  # the command keeps coming, driven by simulated time
            cmd = Twist()
            cmd.linear.x = speed
            last = -1.0
            while not stop.is_set() and not rospy.is_shutdown():
                if now() >= last + 0.05:
                    cmd_pub.publish(cmd)
                    last = now()
                time.sleep(0.002)

        sender = threading.Thread(target=command)
        sender.start()
        try:
            start = now()
            x0 = truth.msg.pose.pose.position.x
            # Free driving first: the wheels turn and odometry follows the truth.
            wait_for(lambda: now() > start + 3.0, 60.0, "3 s of driving")
            wheel_speeds = [abs(v) for n, v in zip(joints.msg.name, joints.msg.velocity) if "wheel" in n]
            self.assertGreater(min(wheel_speeds), 0.8 * speed / 0.2)  # figure5: r_wheel 0.2 m
            self.assertAlmostEqual(odom.msg.pose.pose.position.x, x0 - truth.msg.pose.pose.position.x, delta=0.15)
            # At 0.5 m/s the wall (3.5 m ahead of the centre, minus half the robot) is reached before 9 s.
            wait_for(lambda: now() > start + 9.0, 60.0, "9 s of driving")
            d_wall = odom.msg.pose.pose.position.x
            x_wall = truth.msg.pose.pose.position.x
            wait_for(lambda: now() > start + 12.0, 60.0, "12 s of driving")
            wheel_speeds = [abs(v) for n, v in zip(joints.msg.name, joints.msg.velocity) if "wheel" in n]
        finally:
            stop.set()
            sender.join()
        self.assertLess(abs(truth.msg.pose.pose.position.x - x_wall), 0.01)  # against the wall
        self.assertLess(max(wheel_speeds), 0.1)  # stalled, while 2.5 rad/s is commanded
        self.assertLess(abs(odom.msg.pose.pose.position.x - d_wall), 0.02)  # odometry stopped growing


if __name__ == "__main__":
    rostest.rosrun("thorvald_sim", "physics_encoders", PhysicsEncodersTest)
