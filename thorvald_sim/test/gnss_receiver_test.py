#!/usr/bin/python3
"""The simulated RTK receiver node: from ground truth of a robot standing still (base_link at (10, 5, 0) facing
north, the antenna 0.30 m ahead and 2.46 m up) to NMEA on nmea_sentence. Checks the checksums, the fix states in
order (no fix, single, float, fixed, the scheduled outage, single again) and the fixed solution's position against
the antenna's, converted back with the WGS84 radii of curvature computed here independently."""
import math
import threading
import unittest
from functools import reduce

import rospy
import rostest
from nav_msgs.msg import Odometry
from std_msgs.msg import String

from thorvald_testing import Recorder, wait_for

DATUM = (31.4747, -83.5283, 110.0)
ANTENNA_ENU = (10.0, 5.0 + 0.30, 2.46)  # facing north: the antenna's 0.30 m forward is north


def checksum_ok(sentence):
    body, _, given = sentence[1:].partition("*")
    return sentence.startswith("$") and given == "%02X" % reduce(lambda a, c: a ^ ord(c), body, 0)


def to_enu(lat, lon, alt):
    a, e2 = 6378137.0, 6.69437999014e-3
    s = math.sin(math.radians(DATUM[0]))
    w = math.sqrt(1.0 - e2 * s * s)
    meridian, prime = a * (1.0 - e2) / w ** 3, a / w
    north = math.radians(lat - DATUM[0]) * (meridian + DATUM[2])
    east = math.radians(lon - DATUM[1]) * (prime + DATUM[2]) * math.cos(math.radians(DATUM[0]))
    return east, north, alt - DATUM[2]


def degrees(value, hemisphere, digits):
    d = float(value[:digits]) + float(value[digits:]) / 60.0
    return -d if hemisphere in "SW" else d


class GnssReceiver(unittest.TestCase):
    def test_states_and_position(self):
        sentences = Recorder("nmea_sentence", String, queue_size=1000)
        truth = rospy.Publisher("ground_truth/odom", Odometry, queue_size=10)
        stop = threading.Event()

        def publish():
            rate = rospy.Rate(50)
            while not stop.is_set() and not rospy.is_shutdown():
                o = Odometry()
                o.header.stamp = rospy.Time.now()
                o.header.frame_id = "map"
                o.pose.pose.position.x, o.pose.pose.position.y = 10.0, 5.0
                o.pose.pose.orientation.z = o.pose.pose.orientation.w = math.sqrt(0.5)  # yaw 90 deg: north
                truth.publish(o)
                rate.sleep()

        thread = threading.Thread(target=publish, daemon=True)
        thread.start()
        try:
            def qualities():
                return [int(m.data.split(",")[6]) for m in sentences.since(0) if m.data[3:6] == "GGA"]

            wait_for(lambda: 0 in qualities()[5:] and qualities()[-1] == 1, 20.0, "the outage and a single fix after it")
        finally:
            stop.set()
            thread.join()
        msgs = [m.data for m in sentences.since(0)]
        self.assertTrue(all(checksum_ok(s) for s in msgs), [s for s in msgs if not checksum_ok(s)][:3])
        seq = [q for i, q in enumerate(qualities()) if i == 0 or q != qualities()[i - 1]]
        self.assertEqual(seq[:6], [0, 1, 5, 4, 0, 1], "fix states in order")
        fixed = [s.split(",") for s in msgs if s[3:6] == "GGA" and s.split(",")[6] == "4"]
        self.assertGreater(len(fixed), 5)
        for f in fixed:
            e, n, u = to_enu(degrees(f[2], f[3], 2), degrees(f[4], f[5], 3), float(f[9]))
            self.assertLess(math.hypot(e - ANTENNA_ENU[0], n - ANTENNA_ENU[1]), 0.05, "fixed: within 5 sigma")
            self.assertLess(abs(u - ANTENNA_ENU[2]), 0.10)


if __name__ == "__main__":
    rospy.init_node("gnss_receiver_test")
    rostest.rosrun("thorvald_sim", "gnss_receiver_nmea", GnssReceiver)
