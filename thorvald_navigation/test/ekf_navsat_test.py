#!/usr/bin/python3
"""ekf_localization + navsat_transform (ekf_navsat.test): synthetic wheel odometry (5 % fast), two IMUs and 5 Hz
fixes of a rover driving east at 1 m/s from a datum on zone 31's central meridian; odometry/filtered must follow
the true path, and localization_ok must fall with the reason on diagnostics once the fixes stop."""
import math
import sys
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, NavSatFix, NavSatStatus
from std_msgs.msg import Bool

LAT0, LON0 = 31.0, 3.0  # on the central meridian: grid and true north agree
M_PER_DEG_LON = 111320.0 * math.cos(math.radians(LAT0)) * 0.9996  # UTM grid metres per degree there (near)


class EkfNavsatTest(unittest.TestCase):
    def test_follows_the_path_and_reports_the_lost_fix(self):
        pubs = {
            "odom": rospy.Publisher("odometry/wheel", Odometry, queue_size=10),
            "imu0": rospy.Publisher("imu_front/data", Imu, queue_size=10),
            "imu1": rospy.Publisher("imu_rear/data", Imu, queue_size=10),
            "fix": rospy.Publisher("gps/fix", NavSatFix, queue_size=10),
        }
        seen = {"ok": [], "diag": ""}
        rospy.Subscriber("odometry/filtered", Odometry, lambda m: seen.update(odom=m))
        rospy.Subscriber("localization_ok", Bool, lambda m: seen["ok"].append(m.data))
        rospy.Subscriber("diagnostics", DiagnosticArray, self.on_diag(seen))
        deadline = time.time() + 20.0
        while any(p.get_num_connections() == 0 for p in pubs.values()):
            self.assertLess(time.time(), deadline, "the nodes did not subscribe")
            time.sleep(0.05)
        start = time.time()
        step = 0
        while time.time() - start < 8.0:
            t = time.time() - start
            self.publish(pubs, rospy.Time.now(), t, with_fix=step % 10 == 0)
            step += 1
            time.sleep(0.02)
        time.sleep(0.2)
        m = seen["odom"]
        t = time.time() - start
        rospy.loginfo("odometry/filtered (%.3f, %.3f) at t %.2f", m.pose.pose.position.x, m.pose.pose.position.y, t)
        # Wheels alone would be 5 % ahead (0.4 m after 8 s); the fixes hold the estimate on the path.
        self.assertLess(abs(m.pose.pose.position.x - t), 0.2)
        self.assertLess(abs(m.pose.pose.position.y), 0.1)
        self.assertTrue(seen["ok"] and seen["ok"][-1], "localization_ok while fusing")
        # The fixes stop: within gps_timeout (1 s) plus a cycle the fusion says so.
        seen["ok"].clear()
        stop = time.time()
        while time.time() - stop < 2.5:
            self.publish(pubs, rospy.Time.now(), time.time() - start, with_fix=False)
            time.sleep(0.02)
        self.assertFalse(seen["ok"][-1], "localization_ok after the fixes stopped")
        self.assertIn("odometry/gps", seen["diag"])
        self.assertIn("nothing for", seen["diag"])

    @staticmethod
    def on_diag(seen):
        def cb(msg):
            for s in msg.status:
                if "ekf_localization" in s.name and s.level == 2:
                    seen["diag"] = s.message
        return cb

    @staticmethod
    def publish(pubs, now, t, with_fix):
        o = Odometry()
        o.header.stamp = now
        o.header.frame_id = "odom"
        o.child_frame_id = "base_link"
        o.twist.twist.linear.x = 1.05
        o.twist.covariance[0] = o.twist.covariance[7] = 1e-3
        o.twist.covariance[35] = 1e-3
        pubs["odom"].publish(o)
        for name in ("imu0", "imu1"):
            i = Imu()
            i.header.stamp = now
            i.header.frame_id = "base_link"
            i.orientation.w = 1.0  # facing east
            i.orientation_covariance[0] = i.orientation_covariance[4] = i.orientation_covariance[8] = 1e-4
            i.angular_velocity_covariance[0] = i.angular_velocity_covariance[4] = 1e-4
            i.angular_velocity_covariance[8] = 1e-5
            i.linear_acceleration.z = 9.80665
            i.linear_acceleration_covariance[0] = i.linear_acceleration_covariance[4] = 1e-2
            i.linear_acceleration_covariance[8] = 1e-2
            pubs[name].publish(i)
        if with_fix:
            f = NavSatFix()
            f.header.stamp = now
            f.status.status = NavSatStatus.STATUS_GBAS_FIX
            f.latitude = LAT0
            f.longitude = LON0 + t / M_PER_DEG_LON
            f.position_covariance[0] = f.position_covariance[4] = 4e-4
            f.position_covariance[8] = 1e-3
            f.position_covariance_type = NavSatFix.COVARIANCE_TYPE_DIAGONAL_KNOWN
            pubs["fix"].publish(f)


if __name__ == "__main__":
    rospy.init_node("ekf_navsat_test")
    rostest.rosrun("thorvald_navigation", "ekf_navsat", EkfNavsatTest, sys.argv)
