#!/usr/bin/python3
"""The simulated rover localised through the real chain (launch/rover_localization.launch): its NMEA through
nmea_tcp_feeder, a private gpsd and gpsd_client, its IMUs and wheel odometry, ekf_localization and navsat_transform.
The rover stands until gps/fix reports RTK fixed through gpsd (five epochs), then the cotton_harvester `rover` node
drives it `distance_m` along the row (rover/position_target). Checks: gps/fix RTK fixed (STATUS_GBAS_FIX with the
fixed solution's covariance) from its first fixed epoch on; navsat_transform's
odometry/gps and ekf_localization's odometry/filtered against the simulator's truth (sim/truth/base_link, read only
here), each aligned once at the standing start (the filter's odom frame starts where the rover stood; its axes are the
world's, the IMU's yaw being absolute); the ABSOLUTE position of odometry/filtered, nothing aligned once fixed:
(1) in its odom frame against the truth less the rover's position when the filter started (the filter starts at 0
with the IMU's absolute yaw, the rover standing: the odom frame is the start's; a datum from a single fix offsets
odometry/gps and the filter following it by that fix's error), (2) navsat_transform's gps/filtered
(odometry/filtered's base_link through the datum to latitude and longitude) against the truth's latitude and
longitude (the simulator's world frame is east-north-up at ~sim_datum; the antenna's lever arm not removed offsets
it by the mast's horizontal offset); localization_ok and the filter's position sigma once RTK fixed (the
fixes fused, process noise as in-process); both IMUs at ~imu_rate_hz in simulated time."""
import math
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, NavSatFix, NavSatStatus
from std_msgs.msg import Bool, Float64

from thorvald_testing import Latest, Recorder, wait_for

WGS84_A = 6378137.0
WGS84_E2 = 6.69437999014e-3

FIXED_SIGMA_M = 0.05  # above an RTK fixed solution's 1-sigma (1 cm), well below a float one's (0.3 m)


def stamp(m):
    return m.header.stamp.to_sec()


def rtk_fixed(fix):
    """NavSatFix says GBAS_FIX for RTK float and fixed alike (gpsd_client); the covariance from the receiver's GST
    tells them apart: fixed about 1 cm 1-sigma, float 0.3 m."""
    return (fix.status.status == NavSatStatus.STATUS_GBAS_FIX and
            max(fix.position_covariance[0], fix.position_covariance[4]) <= FIXED_SIGMA_M ** 2)


def ecef(lat_deg, lon_deg, alt_m):
    lat, lon = math.radians(lat_deg), math.radians(lon_deg)
    n = WGS84_A / math.sqrt(1.0 - WGS84_E2 * math.sin(lat) ** 2)
    return ((n + alt_m) * math.cos(lat) * math.cos(lon), (n + alt_m) * math.cos(lat) * math.sin(lon),
            (n * (1.0 - WGS84_E2) + alt_m) * math.sin(lat))


def east_north(datum, lat_deg, lon_deg):
    """East and north [m] of (lat, lon) in the tangent plane at datum (lat, lon, alt): the simulator's world frame."""
    x0, y0, z0 = ecef(*datum)
    x, y, z = ecef(lat_deg, lon_deg, datum[2])
    dx, dy, dz = x - x0, y - y0, z - z0
    lat, lon = math.radians(datum[0]), math.radians(datum[1])
    east = -math.sin(lon) * dx + math.cos(lon) * dy
    north = -math.sin(lat) * math.cos(lon) * dx - math.sin(lat) * math.sin(lon) * dy + math.cos(lat) * dz
    return east, north


def interpolate(track, t):
    """(x, y) of a time-sorted [(t, x, y)] at t (None outside it)."""
    if not track or t < track[0][0] or t > track[-1][0]:
        return None
    lo, hi = 0, len(track) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if track[mid][0] <= t:
            lo = mid
        else:
            hi = mid
    (t0, x0, y0), (t1, x1, y1) = track[lo], track[hi]
    a = 0.0 if t1 == t0 else (t - t0) / (t1 - t0)
    return x0 + a * (x1 - x0), y0 + a * (y1 - y0)


def errors_against_truth(msgs, truth, align_t):
    """Distances [m] of each message's position (after align_t) from the truth, the offset taken at align_t."""
    before = [m for m in msgs if stamp(m) <= align_t]
    if not before:
        return None, []
    ref = before[-1]
    at = interpolate(truth, stamp(ref))
    dx, dy = at[0] - ref.pose.pose.position.x, at[1] - ref.pose.pose.position.y
    out = []
    for m in msgs:
        if stamp(m) <= align_t:
            continue
        t = interpolate(truth, stamp(m))
        if t is None:
            continue
        out.append((stamp(m), math.hypot(m.pose.pose.position.x + dx - t[0], m.pose.pose.position.y + dy - t[1])))
    return ref, out


class RoverLocalization(unittest.TestCase):
    def test_gnss_through_gpsd_and_fusion_against_truth(self):
        imu_rate = rospy.get_param("~imu_rate_hz")
        distance = rospy.get_param("~distance_m")
        max_error = rospy.get_param("~max_error_m")
        max_abs_error = rospy.get_param("~max_absolute_error_m")
        max_sigma = rospy.get_param("~max_sigma_m")
        datum = rospy.get_param("~sim_datum")  # the simulator's world frame: [lat deg, lon deg, alt m] of its origin
        fixes = Recorder("gps/fix", NavSatFix, queue_size=200)
        gps_odom = Recorder("odometry/gps", Odometry, queue_size=200)
        filtered = Recorder("odometry/filtered", Odometry, queue_size=500)
        geo_filtered = Recorder("gps/filtered", NavSatFix, queue_size=500)
        truth_msgs = Recorder("sim/truth/base_link", Odometry, queue_size=2000)
        imus = [Recorder("imu_front/data", Imu, queue_size=5000), Recorder("imu_rear/data", Imu, queue_size=5000)]
        ok = Latest("localization_ok", Bool)
        at_target = Latest("rover/at_target", Bool)
        target = rospy.Publisher("rover/position_target", Float64, queue_size=1, latch=True)

        # Five fixed epochs (1 s) before the alignment: the filter has taken the fixed solution by then.
        wait_for(lambda: sum(rtk_fixed(m) for m in fixes.since(0)) >= 5, 45.0, "RTK fixed gps/fix through gpsd")
        wait_for(lambda: gps_odom.count() >= 3 and filtered.count() >= 3, 15.0, "odometry/gps and odometry/filtered")
        wait_for(lambda: at_target.msg is not None, 10.0, "the rover node's rover/at_target")
        wait_for(lambda: truth_msgs.count() > 0, 5.0, "the simulator's truth")
        align_t = stamp(truth_msgs.last())  # standing: the filter and the fixes are aligned to the truth here
        wait_for(lambda: stamp(filtered.last()) > align_t and stamp(gps_odom.last()) > align_t, 10.0,
                 "odometry after the alignment time")
        start = truth_msgs.last().pose.pose.position
        target.publish(Float64(data=distance))

        def travelled():
            p = truth_msgs.last().pose.pose.position
            return math.hypot(p.x - start.x, p.y - start.y)

        wait_for(lambda: travelled() > 0.5 * distance and at_target.msg.data, 40.0,
                 "the rover at %.1f m along the row" % distance)
        end_t = stamp(truth_msgs.last())
        wait_for(lambda: stamp(filtered.last()) > end_t + 1.0, 10.0, "odometry/filtered 1 s past the stop")

        truth = [(stamp(m), m.pose.pose.position.x, m.pose.pose.position.y) for m in truth_msgs.since(0)]
        all_fixes = fixes.since(0)
        first_rtk = next(i for i, m in enumerate(all_fixes) if rtk_fixed(m))
        rtk = [m for m in all_fixes if rtk_fixed(m)]
        self.assertGreaterEqual(len(rtk), 0.9 * (len(all_fixes) - first_rtk), "gps/fix RTK fixed once fixed (open sky)")

        _, gps_err = errors_against_truth(gps_odom.since(0), truth, align_t)
        _, ekf_err = errors_against_truth(filtered.since(0), truth, align_t)
        self.assertGreater(len(gps_err), 10)
        self.assertGreater(len(ekf_err), 30)
        gps_max = max(e for _, e in gps_err)
        ekf_max = max(e for _, e in ekf_err)
        rospy.loginfo("rover_localization: drove %.2f m; gps/fix %d (RTK fixed %d, the first one %d-th); odometry/gps %d, "
                      "max error %.3f m; odometry/filtered %d, max error %.3f m, at the end %.3f m", travelled(),
                      len(all_fixes), len(rtk), first_rtk + 1, len(gps_err), gps_max, len(ekf_err), ekf_max,
                      ekf_err[-1][1])
        self.assertGreater(travelled(), 0.5 * distance)
        self.assertLess(gps_max, max_error, "navsat_transform's odometry/gps against the truth")
        self.assertLess(ekf_max, max_error, "ekf_localization's odometry/filtered against the truth")
        self.assertTrue(ok.msg is not None and ok.msg.data, "localization_ok")

        # Absolute (1): odometry/filtered in its odom frame, whose origin is base_link where the rover stood when the
        # filter started (its first message; the truth then, or the first truth if it began later: standing still).
        first = filtered.since(0)[0]
        start_at = interpolate(truth, stamp(first)) or (truth[0][1], truth[0][2])
        odom_err = []
        for m in filtered.since(0):
            at = interpolate(truth, stamp(m))
            if stamp(m) <= align_t or at is None:
                continue
            odom_err.append(math.hypot(m.pose.pose.position.x - (at[0] - start_at[0]),
                                       m.pose.pose.position.y - (at[1] - start_at[1])))
        self.assertGreater(len(odom_err), 30)
        odom_max = max(odom_err)
        rospy.loginfo("rover_localization: odometry/filtered ABSOLUTE in the odom frame (the truth less the start at "
                      "%.3f, %.3f, no alignment) %d messages, max error %.3f m, mean %.3f m, at the end %.3f m",
                      start_at[0], start_at[1], len(odom_err), odom_max, sum(odom_err) / len(odom_err), odom_err[-1])

        # Absolute (2): odometry/filtered through navsat_transform's datum (gps/filtered) against the truth, both in
        # the simulator's east-north-up frame, from the alignment time (RTK fixed five epochs) to the end.
        abs_err = []
        for m in geo_filtered.since(0):
            at = interpolate(truth, stamp(m))
            if stamp(m) <= align_t or at is None:
                continue
            e, n = east_north(datum, m.latitude, m.longitude)
            abs_err.append(math.hypot(e - at[0], n - at[1]))
        self.assertGreater(len(abs_err), 30, "gps/filtered (odometry/filtered's latitude and longitude)")
        abs_max = max(abs_err)
        rospy.loginfo("rover_localization: odometry/filtered ABSOLUTE through the datum (gps/filtered against the truth) "
                      "%d messages, max error %.3f m, mean %.3f m, at the end %.3f m", len(abs_err), abs_max,
                      sum(abs_err) / len(abs_err), abs_err[-1])
        self.assertLess(odom_max, max_abs_error, "odometry/filtered's position in the odom frame against the truth")
        self.assertLess(abs_max, max_abs_error, "odometry/filtered's latitude and longitude against the truth")

        # The filter's own 1-sigma of x and y once RTK fixed (from the alignment to the end): its x, y variance grows
        # with the process noise between fixes and falls to the fix's at each fused one; at robot_localization's
        # default process noise (0.05 m^2/s) it saws up to 0.1 m between 5 Hz fixes, from wheel odometry and IMUs
        # alone it would be above 0.7 m after the drive.
        fixed = [m for m in filtered.since(0) if stamp(m) > align_t]
        sigmas = [math.sqrt(max(m.pose.covariance[0], m.pose.covariance[7])) for m in fixed]
        rospy.loginfo("rover_localization: odometry/filtered's x, y 1-sigma once RTK fixed %.4f-%.4f m (%d messages)",
                      min(sigmas), max(sigmas), len(sigmas))
        self.assertLess(max(sigmas), max_sigma, "the filter's position sigma once RTK fixed")

        # Both IMUs at the configured rate in simulated time, no sample missing (the physics' 2 ms step quantises
        # each stamp; the mean period is the configured one).
        for name, rec in zip(("imu_front/data", "imu_rear/data"), imus):
            stamps = sorted(stamp(m) for m in rec.since(0))
            self.assertGreater(len(stamps), 2 * imu_rate, "%s: %d messages" % (name, len(stamps)))
            rate = (len(stamps) - 1) / (stamps[-1] - stamps[0])
            gaps = [b - a for a, b in zip(stamps, stamps[1:])]
            rospy.loginfo("rover_localization: %s %d messages over %.2f s simulated: %.2f Hz, gaps %.4f-%.4f s", name,
                          len(stamps), stamps[-1] - stamps[0], rate, min(gaps), max(gaps))
            self.assertLess(abs(rate - imu_rate), 0.01 * imu_rate, "%s at %.2f Hz" % (name, rate))
            self.assertLess(max(gaps), 1.5 / imu_rate, "%s: a sample missing" % name)


if __name__ == "__main__":
    rospy.init_node("test_rover_localization")
    rostest.rosrun("cotton_harvester_sim", "rover_localization", RoverLocalization)
