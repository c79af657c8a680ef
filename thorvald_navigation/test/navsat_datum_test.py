#!/usr/bin/python3
"""navsat_transform's datum and lever arm (navsat_datum.test): single fixes (1.5 m sigma) set no datum and the
diagnostics say it waits for a good enough fix; the first RTK fixed one (1 cm) sets it; a fix from the antenna of a
robot rolled 0.1 rad comes out as base_link's; with ~datum a single fix is transformed at once."""
import math
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, NavSatFix, NavSatStatus

LAT0, LON0 = 31.0, 3.0  # on zone 31's central meridian: grid and true north agree
M_PER_DEG_LAT = 110861.0  # WGS84 metres per degree of latitude at 31 deg
M_PER_DEG_LON = 111320.0 * math.cos(math.radians(LAT0)) * (1.0 - 0.00335 * math.sin(math.radians(LAT0)) ** 2) ** -0.5
MOUNT = (0.2, 0.0, 2.0)  # gps_link in base_link (navsat_datum.test's static transform)


def fix(east, north, sigma, frame="gps_link"):
    f = NavSatFix()
    f.header.stamp = rospy.Time.now()
    f.header.frame_id = frame
    f.status.status = NavSatStatus.STATUS_GBAS_FIX
    f.latitude = LAT0 + north / M_PER_DEG_LAT
    f.longitude = LON0 + east / M_PER_DEG_LON
    f.position_covariance[0] = f.position_covariance[4] = sigma ** 2
    f.position_covariance[8] = (2 * sigma) ** 2
    f.position_covariance_type = NavSatFix.COVARIANCE_TYPE_DIAGONAL_KNOWN
    return f


def imu(roll):
    m = Imu()
    m.header.stamp = rospy.Time.now()
    m.header.frame_id = "base_link"
    m.orientation.x = math.sin(0.5 * roll)  # roll about x, yaw 0 (facing east)
    m.orientation.w = math.cos(0.5 * roll)
    m.orientation_covariance[0] = m.orientation_covariance[4] = m.orientation_covariance[8] = 1e-4
    return m


class NavsatDatum(unittest.TestCase):
    def wait(self, cond, timeout, what, each=None):
        deadline = time.time() + timeout
        while not cond():
            self.assertLess(time.time(), deadline, "timed out waiting for " + what)
            if each:
                each()
            time.sleep(0.2)

    def test_datum_waits_for_a_good_fix_and_the_fix_is_base_links(self):
        gps = rospy.Publisher("gps/fix", NavSatFix, queue_size=10)
        imu_pub = rospy.Publisher("imu/data", Imu, queue_size=10)
        out, diag = [], {}
        rospy.Subscriber("odometry/gps", Odometry, out.append)

        def on_diag(msg):
            for s in msg.status:
                if s.name.startswith("navsat_transform"):
                    diag["msg"] = s.message
        rospy.Subscriber("/diagnostics", DiagnosticArray, on_diag)
        self.wait(lambda: gps.get_num_connections() > 0 and imu_pub.get_num_connections() > 0, 20.0, "the node")

        # Single fixes, the robot level: no datum, no output; the diagnostics say why.
        def single():
            imu_pub.publish(imu(0.0))
            gps.publish(fix(0.2, 0.0, 1.5))
        self.wait(lambda: "good enough for the datum" in diag.get("msg", ""), 5.0, "the diagnostics' wait", single)
        rospy.loginfo("navsat_datum: diagnostics while single: %s", diag["msg"])
        self.assertIn("1.5 m", diag["msg"])
        self.assertEqual(out, [], "odometry/gps before the datum")

        # An RTK fixed fix at the antenna, robot level at the world origin: the datum; odometry/gps is base_link's
        # (0, 0), not the antenna's (0.2, 0).
        def fixed():
            imu_pub.publish(imu(0.0))
            gps.publish(fix(0.2, 0.0, 0.01))
        self.wait(lambda: out, 5.0, "odometry/gps after an RTK fixed fix", fixed)
        p = out[-1].pose.pose.position
        rospy.loginfo("navsat_datum: at the datum (%.4f, %.4f)", p.x, p.y)
        self.assertLess(math.hypot(p.x, p.y), 0.005)

        # base_link 1 m east, rolled 0.1 rad (about x): the antenna is at base + R(roll) * mount.
        roll = 0.1
        ax = 1.0 + MOUNT[0]
        ay = MOUNT[1] * math.cos(roll) - MOUNT[2] * math.sin(roll)
        n = len(out)

        def moved():
            imu_pub.publish(imu(roll))
            gps.publish(fix(ax, ay, 0.01))
        self.wait(lambda: len(out) > n + 2, 5.0, "odometry/gps of the rolled robot", moved)
        p = out[-1].pose.pose.position
        rospy.loginfo("navsat_datum: rolled robot at (%.4f, %.4f), the antenna at (%.4f, %.4f)", p.x, p.y, ax, ay)
        self.assertLess(math.hypot(p.x - 1.0, p.y), 0.01, "base_link's position from the antenna's fix")

    def test_datum_parameter_wins(self):
        gps = rospy.Publisher("with_datum/gps/fix", NavSatFix, queue_size=10)
        out = []
        rospy.Subscriber("with_datum/odometry/gps", Odometry, out.append)
        self.wait(lambda: gps.get_num_connections() > 0, 20.0, "the node with ~datum")
        # A single fix 3 m north of the datum, its frame base_link (no lever arm): used at once.
        self.wait(lambda: out, 5.0, "odometry/gps from a single fix with ~datum",
                  lambda: gps.publish(fix(0.0, 3.0, 1.5, frame="base_link")))
        p = out[-1].pose.pose.position
        rospy.loginfo("navsat_datum: with ~datum, a single fix 3 m north at (%.4f, %.4f)", p.x, p.y)
        self.assertLess(math.hypot(p.x, p.y - 3.0), 0.01)


if __name__ == "__main__":
    rospy.init_node("navsat_datum_test")
    rostest.rosrun("thorvald_navigation", "navsat_datum", NavsatDatum)
