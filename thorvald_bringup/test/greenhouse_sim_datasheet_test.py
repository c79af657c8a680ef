#!/usr/bin/python3
"""The greenhouse robot's sensors in the datasheet profile on known geometry (greenhouse_sim_datasheet.test): depth
noise on the floor against 0.01 z^2, holes in the pipes' glint band, the IMU's offset from its reading at rest, the
range finders over the floor, the lidar at the rear wall. Every figure is printed."""
import array
import math
import struct
import unittest
import zlib

import rospy
import rostest
import yaml
from sensor_msgs.msg import CameraInfo, Imu, LaserScan, PointCloud2, Range
from thorvald_testing import Recorder, wait_for

DEPTH_NOISE = 0.01  # thorvald_sim README, active stereo noise_coeff: sigma_z = 0.01 z^2
LIDAR_SIGMA = 0.010  # UTM-30LX sigma_near (below 10 m)
FRAMES = 12
SKIP_U = 80  # the left invalid band (baseline fx / z) is narrower than this at z >= 0.4 m
SHINY_BAND = 0.35  # thorvald_sim README, active stereo shiny_band: no depth within 0.35 rad of the glint line
# The pipes in base_link (sim_greenhouse_world.launch: rail_top 0.06, thorvald_sim's 51 mm pipes, 0.55 m gauge;
# the robots stand on the rail sets' centre lines).
PIPE_R = 0.0255
PIPE_Z = 0.06 - PIPE_R
PIPE_Y = 0.275


def camera_mount(sensors_file):
    with open(sensors_file) as f:
        cam = [s for s in yaml.safe_load(f)["sensors"] if s["type"] == "depth_camera"][0]
    return cam["xyz"], cam.get("rpy", [0.0, 0.0, 0.0])[1]


def to_base(p, mount):
    """Optical-frame point (z forward, x right, y down) to base_link for a camera pitched down by mount[1]."""
    (tx, ty, tz), pitch = mount
    cx, cy, cz = p[2], -p[0], -p[1]  # camera body frame: x forward, y left, z up
    c, s = math.cos(pitch), math.sin(pitch)
    return (c * cx + s * cz + tx, cy + ty, -s * cx + c * cz + tz)


def depth_frames(msgs):
    """z (optical) of every pixel, NaN where no depth, one flat array per frame; and the image width."""
    out = []
    for m in msgs:
        offs = {f.name: f.offset for f in m.fields}
        a = array.array("f")
        a.frombytes(bytes(m.data))
        stride, oz = m.point_step // 4, offs["z"] // 4
        out.append(a[oz::stride])
    return out, msgs[0].width


def points(msg):
    offs = {f.name: f.offset for f in msg.fields}
    a = array.array("f")
    a.frombytes(bytes(msg.data))
    stride = msg.point_step // 4
    ox, oy, oz = offs["x"] // 4, offs["y"] // 4, offs["z"] // 4
    return [(a[i + ox], a[i + oy], a[i + oz]) for i in range(0, len(a), stride)]


def write_png(path, width, height, rows):
    """8-bit RGB PNG (rows: lists of (r, g, b))."""
    raw = b"".join(b"\x00" + bytes(v for px in row for v in px) for row in rows)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def depth_colour(z, lo=0.4, hi=4.0):
    if math.isnan(z):
        return (0, 0, 0)
    t = min(1.0, max(0.0, (z - lo) / (hi - lo)))
    return (int(255 * (1 - t)), int(255 * (1 - abs(2 * t - 1))), int(255 * t))


class GreenhouseDatasheetTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("greenhouse_sim_datasheet_test")
        cls.mount = camera_mount(rospy.get_param("~sensors"))
        cls.info = rospy.wait_for_message("/d1/camera/depth/camera_info", CameraInfo, timeout=120.0)
        cls.imu = {r: Recorder("/%s/imu" % r, Imu, queue_size=500) for r in ("d1", "i1")}
        cls.scan = Recorder("/d2/scan", LaserScan, queue_size=100)
        cls.ranges = {n: Recorder("/d1/ultrasonic/%s" % n, Range) for n in
                      ("front_right", "front_left", "mid_right", "mid_left")}
        # Let the robots settle on their wheels before anything is sampled.
        wait_for(lambda: rospy.get_time() > 1.0, 120.0, "1 s of simulated time")
        cls.clouds = {r: Recorder("/%s/camera/depth/points" % r, PointCloud2, queue_size=2) for r in ("d1", "i1")}
        for rec in cls.clouds.values():
            rec.wait_count(FRAMES, timeout=150.0)
        for rec in cls.clouds.values():
            rec.sub.unregister()
        cls.frames = {r: depth_frames(rec.since(0)[:FRAMES])[0] for r, rec in cls.clouds.items()}
        cls.width = cls.info.width
        cls.ideal_points = points(cls.clouds["i1"].since(0)[0])

    def pixel_ray_floor_depth(self, u, v):
        """Optical z where pixel (u, v)'s ray meets the floor (z = 0 in base_link), None above the horizon."""
        k = self.info.K
        d = ((u - k[2]) / k[0], (v - k[5]) / k[4], 1.0)
        o = to_base((0.0, 0.0, 0.0), self.mount)
        e = to_base(d, self.mount)
        dz = e[2] - o[2]
        return -o[2] / dz if dz < -1e-6 else None

    def floor_noise(self, robot, z_lo, z_hi):
        """sigma_z / z^2 from the pixel-wise spread over the frames (z: the pixel's mean depth), on the floor between
        the rails (the known plane picks the pixels) at optical depths z_lo..z_hi; and the number of pixels."""
        w, k, ratios = self.width, self.info.K, []
        for v in range(0, self.info.height, 2):
            for u in range(SKIP_U, w, 2):
                z0 = self.pixel_ray_floor_depth(u, v)
                if z0 is None or not z_lo <= z0 < z_hi:
                    continue
                p = to_base(((u - k[2]) / k[0] * z0, (v - k[5]) / k[4] * z0, z0), self.mount)
                if not (0.7 <= p[0] <= 2.5 and abs(p[1]) <= 0.15):  # floor between the rails
                    continue
                zs = [z for z in (f[v * w + u] for f in self.frames[robot]) if not math.isnan(z)]
                if len(zs) < FRAMES - 2:
                    continue
                m = sum(zs) / len(zs)
                ratios.append(sum((z - m) ** 2 for z in zs) / (len(zs) - 1) / m ** 4)
        return (math.sqrt(sum(ratios) / len(ratios)) if ratios else float("nan")), len(ratios)

    def test_depth_noise_on_the_floor_grows_with_z_squared(self):
        """0.01 z^2 (the datasheet) within 15 % near (0.8-1.2 m) and farther (1.2-2.6 m); the ideal profile's 0.002 z^2
        as a control."""
        near, n = self.floor_noise("d1", 0.8, 1.2)
        far, n_far = self.floor_noise("d1", 1.2, 2.6)
        ideal, n_ideal = self.floor_noise("i1", 0.8, 1.2)
        print("depth noise on the floor: sigma_z / z^2 = %.5f /m at 0.8-1.2 m (%d px; datasheet %.3f), %.5f at "
              "1.2-2.6 m (%d px); ideal profile %.5f at 0.8-1.2 m (%d px)" %
              (near, n, DEPTH_NOISE, far, n_far, ideal, n_ideal))
        self.assertGreater(n, 200, "floor pixels between the rails")
        self.assertLess(abs(near - DEPTH_NOISE), 0.15 * DEPTH_NOISE)
        self.assertLess(abs(far - DEPTH_NOISE), 0.15 * DEPTH_NOISE)
        self.assertLess(abs(ideal - 0.002), 0.15 * 0.002)

    def pipe_pixels(self):
        """Pixels on a pipe in i1's first frame (6-80 mm up, beside the rails' centre line), from SKIP_U on."""
        w = self.width
        pipe = []
        for i, p in enumerate(self.ideal_points):
            if math.isnan(p[2]) or i % w < SKIP_U:
                continue
            b = to_base(p, self.mount)
            if 0.006 < b[2] < 0.08 and 0.4 < b[0] < 3.0 and 0.15 < abs(b[1]) < 0.45:
                pipe.append(i)
        return pipe

    def glint_angle(self, i, side):
        """The angle of pixel i's surface normal from the plane through the pipe's axis and the camera (thorvald_sim's
        glintAngle), the pixel's ray met with the known pipe on `side` (+1 left, -1 right); None if it misses."""
        k, u, v = self.info.K, i % self.width, i // self.width
        o = to_base((0.0, 0.0, 0.0), self.mount)
        e = to_base(((u - k[2]) / k[0], (v - k[5]) / k[4], 1.0), self.mount)
        d = [e[j] - o[j] for j in range(3)]
        yc, zc = o[1] - side * PIPE_Y, o[2] - PIPE_Z  # camera from the axis, across the pipe
        a = d[1] ** 2 + d[2] ** 2
        bq = 2 * (yc * d[1] + zc * d[2])
        disc = bq * bq - 4 * a * (yc * yc + zc * zc - PIPE_R ** 2)
        if disc < 0:
            return None
        t = (-bq - math.sqrt(disc)) / (2 * a)
        ny, nz = (yc + t * d[1]) / PIPE_R, (zc + t * d[2]) / PIPE_R  # the unit normal (its x part is 0)
        qn = math.hypot(yc, zc)  # q = x * (camera - axis) = (0, -zc, yc)
        return math.asin(min(1.0, abs(-ny * zc + nz * yc) / qn))

    def test_pipe_glint_band_has_no_depth(self):
        """The pipes lose depth in their glint band (normal within SHINY_BAND of the plane through the axis and the
        camera) and keep it elsewhere; the share lost is the share of pipe pixels in the band by the pipes' known
        geometry (pixels within 0.1 rad of the band's edge are left out of the in/out checks: the pixel's footprint
        and the robots' settling)."""
        pipe = self.pipe_pixels()
        self.assertGreater(len(pipe), 1000, "pipe pixels in the ideal image")
        glint = {}
        for i in pipe:
            g = self.glint_angle(i, 1 if to_base(self.ideal_points[i], self.mount)[1] > 0 else -1)
            if g is not None:
                glint[i] = g
        inside = [i for i, g in glint.items() if g < SHINY_BAND - 0.1]
        outside = [i for i, g in glint.items() if g > SHINY_BAND + 0.1]
        want = sum(g < SHINY_BAND for g in glint.values()) / float(len(glint))
        floor = [i for i in range(len(self.ideal_points)) if i % self.width >= SKIP_U and i % 7 == 0 and
                 i not in glint and not math.isnan(self.ideal_points[i][2])]

        def nan_frac(robot, idx):
            fr = self.frames[robot]
            return sum(math.isnan(f[i]) for f in fr for i in idx) / float(len(fr) * len(idx))

        ds_all, ideal_all = nan_frac("d1", list(glint)), nan_frac("i1", list(glint))
        ds_in, ds_out, ds_rest = nan_frac("d1", inside), nan_frac("d1", outside), nan_frac("d1", floor)
        print("no depth on the visible pipe (%d px, %d met by their rays): datasheet %.3f for %.3f in the band by "
              "geometry, ideal %.3f" % (len(pipe), len(glint), ds_all, want, ideal_all))
        print("no depth well inside the glint band (%d px) %.3f, well outside (%d px) %.3f; elsewhere (datasheet) "
              "%.3f" % (len(inside), ds_in, len(outside), ds_out, ds_rest))
        self.assertGreater(len(glint), 0.8 * len(pipe))
        self.assertGreater(len(inside), 200)
        self.assertGreater(len(outside), 200)
        self.assertGreater(ds_in, 0.9)
        self.assertLess(ds_out, 0.1)
        self.assertLess(abs(ds_all - want), 0.15 * want)
        self.assertLess(ideal_all, 0.05)
        png = rospy.get_param("~figure_png", "")
        if png:
            w, h = self.width, self.info.height
            d, i = self.frames["d1"][0], self.frames["i1"][0]
            rows = [[depth_colour(i[v * w + u]) for u in range(w)] + [(255, 255, 255)] * 8 +
                    [depth_colour(d[v * w + u]) for u in range(w)] for v in range(h)]
            write_png(png, 2 * w + 8, h, rows)
            print("wrote %s (left ideal, right datasheet)" % png)

    def test_imu_offset_beyond_white_noise(self):
        """The datasheet IMU's mean over 10 s standing still differs from the reading at rest (no rate, gravity's
        reaction 9.81 m/s^2 up) by more than its white noise allows: bias and scale factor are there; the z offset is
        within 3 sigma of the UM7 figures (scale factor 1 % of 9.81, bias 0.005). The ideal twin is printed, not
        compared against: its body chatters on its contacts (accel z std dev near 1 m/s^2 in this world), so its 10 s
        mean wanders by tenths of a m/s^2 from run to run."""
        n = 1000
        start = {r: rec.count() for r, rec in self.imu.items()}
        wait_for(lambda: all(rec.count() >= start[r] + n for r, rec in self.imu.items()), 120.0,
                 "%d more IMU readings" % n)

        def stats(robot):
            msgs = self.imu[robot].since(start[robot])[:n]
            axes = [[m.angular_velocity.x for m in msgs], [m.angular_velocity.y for m in msgs],
                    [m.angular_velocity.z for m in msgs], [m.linear_acceleration.x for m in msgs],
                    [m.linear_acceleration.y for m in msgs], [m.linear_acceleration.z for m in msgs]]
            out = []
            for a in axes:
                m = sum(a) / len(a)
                out.append((m, sum((x - m) ** 2 for x in a) / (len(a) - 1)))
            return out

        rest = [0.0, 0.0, 0.0, 0.0, 0.0, 9.81]
        ds, ideal = stats("d1"), stats("i1")
        z = [(a[0] - r) / math.sqrt(a[1] / n) for a, r in zip(ds, rest)]
        chi2 = sum(x * x for x in z)
        print("IMU mean offset from rest over %d readings (gyro rad/s, accel m/s^2): datasheet %s (chi2 over 6 axes "
              "%.1f, accel z std dev %.3f); ideal %s (accel z std dev %.3f)" %
              (n, ", ".join("%+.5f" % (a[0] - r) for a, r in zip(ds, rest)), chi2, math.sqrt(ds[5][1]),
               ", ".join("%+.5f" % (a[0] - r) for a, r in zip(ideal, rest)), math.sqrt(ideal[5][1])))
        self.assertGreater(chi2, 30.0)  # p < 1e-5 for no offset (chi2 with 6 degrees of freedom)
        self.assertLess(abs(ds[5][0] - 9.81), 3.0 * math.hypot(0.01 * 9.81, 0.005))

    def test_range_finders_over_the_floor(self):
        for name, rec in self.ranges.items():
            rec.wait_count(20, timeout=60.0)
            r = sorted(m.range for m in rec.since(0) if math.isfinite(m.range))
            self.assertTrue(r, name)
            median = r[len(r) // 2]
            print("range finder %s: median %.3f m over %d echoes" % (name, median, len(r)))
            self.assertLess(abs(median - 0.35), 0.03, name)

    def test_lidar_noise_at_the_rear_wall(self):
        self.scan.wait_count(40, timeout=120.0)
        scans = self.scan.since(0)[-40:]
        s0 = scans[0]
        wall = rospy.get_param("~d2_x") - 0.45 - rospy.get_param("~rear_wall_x")  # lidar 0.45 m ahead
        stds, biases = [], []
        for k in range(len(s0.ranges)):
            a = s0.angle_min + k * s0.angle_increment
            if abs(a) > 0.17:
                continue
            r = [s.ranges[k] for s in scans if math.isfinite(s.ranges[k])]
            if len(r) < 30:
                continue
            m = sum(r) / len(r)
            stds.append(sum((x - m) ** 2 for x in r) / (len(r) - 1))
            biases.append(m - wall / math.cos(a))
        self.assertGreater(len(stds), 50)
        sigma = math.sqrt(sum(stds) / len(stds))
        bias = sum(biases) / len(biases)
        print("lidar at the rear wall (%.2f m): sigma %.4f m over %d beams (datasheet %.3f), mean error %+.4f m" %
              (wall, sigma, len(stds), LIDAR_SIGMA, bias))
        self.assertLess(abs(sigma - LIDAR_SIGMA), 0.15 * LIDAR_SIGMA)
        self.assertLess(abs(bias), 0.03)


if __name__ == "__main__":
    rostest.rosrun("thorvald_bringup", "greenhouse_sim_datasheet", GreenhouseDatasheetTest)
