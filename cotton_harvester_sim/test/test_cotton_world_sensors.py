#!/usr/bin/python3
"""The cotton world's sensors in the datasheet profile, from their topics (cotton_world_sensors.test).

The rover stands still, so every pixel sees the same surface in each frame and only the ZED model's noise changes
from frame to frame: the per-pixel spread of z over the frames, over the pixels of a 0.1 m range band, is the
model's sigma_z = z^2 sigma_d / (f B) (sigma_d 0.25 px, B 0.12 m, f from camera_info). The band's estimate is the
median of the pixels' variance over the model's (a few leaves still swing and depth edges between plant parts
move: their pixels' spread is 1.2-1.9 times the model's, so a pooled mean would fail there). Tolerance 10 %: the
median over thousands of pixels is within about 2 % of the truth, the model's normal deviates have a variance
within 0.2 % of 1 (tails cut at 3.67 sigma, thorvald_sim's pixel_noise.h), the cloud's float32 and the mean's own
noise add less than 0.1 %; what remains is room for a plant part still swinging after settle_s.
Holes: no depth on saturated pixels (a channel >= 250) nor on textureless ones (the 7x7 window's grey std dev < 2).
"""
import threading
import unittest

import numpy as np
import rospy
import rostest
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, PointCloud2

BASELINE_M = 0.12  # PassiveStereoModel's defaults (thorvald_sim/stereo_models.h), the README's ZED rows
DISPARITY_SIGMA_PX = 0.25
WINDOW = 7
MIN_TEXTURE_SIGMA = 2.0
SATURATION = 250


def cloud_z(msg):
    """The organised cloud's z as a height x width float array (NaN where no depth)."""
    field = next(f for f in msg.fields if f.name == "z")
    raw = np.frombuffer(msg.data, dtype=np.uint8).reshape(msg.height, msg.row_step)
    cols = raw[:, : msg.width * msg.point_step].reshape(msg.height, msg.width, msg.point_step)
    return cols[:, :, field.offset : field.offset + 4].copy().view(np.float32)[:, :, 0]


def image_bgr(msg):
    return np.frombuffer(msg.data, dtype=np.uint8).reshape(msg.height, msg.step)[:, : 3 * msg.width].reshape(
        msg.height, msg.width, 3
    )


def window_std(grey, w):
    """Std dev of grey over the w x w window around each pixel, clipped at the border (as the model)."""
    h, wd = grey.shape
    half = w // 2
    s = np.zeros((h + 1, wd + 1))
    q = np.zeros((h + 1, wd + 1))
    s[1:, 1:] = grey.cumsum(0).cumsum(1)
    q[1:, 1:] = (grey * grey).cumsum(0).cumsum(1)
    v0 = np.clip(np.arange(h) - half, 0, h)[:, None]
    v1 = np.clip(np.arange(h) + half + 1, 0, h)[:, None]
    u0 = np.clip(np.arange(wd) - half, 0, wd)[None, :]
    u1 = np.clip(np.arange(wd) + half + 1, 0, wd)[None, :]

    def box(a):
        return a[v1, u1] - a[v0, u1] - a[v1, u0] + a[v0, u0]

    cnt = (v1 - v0) * (u1 - u0)
    mean = box(s) / cnt
    return np.sqrt(np.maximum(box(q) / cnt - mean * mean, 0.0))


class CottonWorldSensorsTest(unittest.TestCase):
    def test_datasheet_sensors(self):
        rospy.init_node("test_cotton_world_sensors")
        rate = rospy.get_param("~camera_rate_hz")
        settle = rospy.get_param("~settle_s")
        wanted = rospy.get_param("~frames")
        lock = threading.Lock()
        got = {"images": {}, "clouds": {}, "info": None, "clock": []}

        def keep(kind):
            def cb(msg):
                with lock:
                    if msg.header.stamp.to_sec() - 1.0 >= settle:  # the sim's time starts at 1 s (ROS time)
                        got[kind][msg.header.stamp.to_nsec()] = msg

            return cb

        def on_info(msg):
            with lock:
                got["info"] = msg

        def on_clock(msg):
            with lock:
                got["clock"].append(msg.clock.to_sec())

        rospy.Subscriber("camera/color/image_raw", Image, keep("images"), queue_size=50)
        rospy.Subscriber("camera/depth/points", PointCloud2, keep("clouds"), queue_size=50, buff_size=2**26)
        rospy.Subscriber("camera/color/camera_info", CameraInfo, on_info, queue_size=5)
        rospy.Subscriber("/clock", Clock, on_clock, queue_size=1000)
        deadline = rospy.get_time() + 75.0
        while not rospy.is_shutdown() and rospy.get_time() < deadline:
            with lock:
                both = sorted(set(got["images"]) & set(got["clouds"]))
            if len(both) >= wanted:
                break
            rospy.sleep(0.1)
        with lock:
            stamps = both[:wanted]
            images = [got["images"][s] for s in stamps]
            clouds = [got["clouds"][s] for s in stamps]
            info, clock = got["info"], list(got["clock"])
        self.assertEqual(len(stamps), wanted, "camera frames after the plants settled")

        # The camera's rate in simulated time, its intrinsics and the clock.
        # Every frame on the camera's grid in simulated time: each gap a whole number of periods (the simulator renders
        # every period; a 30 MB cloud the test reads slower than the publisher's queue of 2 is dropped in transport on
        # a loaded machine, so a gap of two periods is a frame this test did not get, not one the camera skipped).
        gaps = np.diff(np.array(stamps, dtype=np.float64) * 1e-9)
        periods = gaps * rate
        self.assertTrue(
            np.all(periods >= 0.5) and np.allclose(periods, np.round(periods), atol=0.02 * rate), "frame gaps %s s" % gaps
        )
        self.assertIsNotNone(info)
        self.assertEqual((info.width, info.height), (1280, 720))
        self.assertAlmostEqual(info.K[0], 699.936, places=3)
        self.assertGreater(len(clock), 10)
        self.assertTrue(all(b >= a for a, b in zip(clock, clock[1:])), "/clock went back")
        fx = info.K[0]

        z = np.stack([cloud_z(c) for c in clouds]).astype(np.float64)
        bgr = np.stack([image_bgr(i) for i in images]).astype(np.float64)
        holes = np.isnan(z)

        # Holes: every saturated pixel and every textureless one has no depth.
        saturated = bgr.max(axis=3) >= SATURATION
        flat = np.stack([window_std(b.mean(axis=2), WINDOW) for b in bgr]) < 0.95 * MIN_TEXTURE_SIGMA
        flat &= ~saturated
        rospy.loginfo(
            "saturated pixels %d (%.2f %% of the image), textureless %d, holes overall %.1f %%",
            saturated.sum(),
            100.0 * saturated.mean(),
            flat.sum(),
            100.0 * holes.mean(),
        )
        self.assertGreater(saturated.sum() + flat.sum(), 1000, "no saturated or textureless patch in view")
        self.assertTrue(holes[saturated].all(), "%d saturated pixels with depth" % (~holes[saturated]).sum())
        self.assertTrue(holes[flat].all(), "%d textureless pixels with depth" % (~holes[flat]).sum())
        textured = (np.stack([window_std(b.mean(axis=2), WINDOW) for b in bgr]) > 1.05 * MIN_TEXTURE_SIGMA) & ~saturated
        rospy.loginfo("holes on textured pixels %.2f %%", 100.0 * holes[textured].mean())
        # Left-right occlusion only: the left band the right camera does not see (fB / z = 40-70 px of 1280) and the
        # strips beside the plants and the housing (10.0 % measured, seed 7).
        self.assertLess(holes[textured].mean(), 0.15, "holes on textured pixels")

        # Depth noise against sigma_z = z^2 sigma_d / (f B) in range bands of 0.1 m.
        valid = ~holes.any(axis=0)
        mean_z = np.where(valid, z.mean(axis=0), np.nan)
        var = z.var(axis=0, ddof=1)
        checked = []
        for lo in np.arange(0.5, 3.0, 0.1):
            band = valid & (mean_z >= lo) & (mean_z < lo + 0.1)
            if band.sum() < 2000:
                continue
            model_var = (mean_z[band] ** 2 * DISPARITY_SIGMA_PX / (fx * BASELINE_M)) ** 2
            # The median of each pixel's variance over the model's, against the median of chi2(N-1) / (N-1)
            # (Wilson-Hilferty): a pixel on a plant part that still moves, or on a depth edge, does not pull it.
            k = len(stamps) - 1
            chi2_median = (1.0 - 2.0 / (9.0 * k)) ** 3
            ratio = np.sqrt(np.median(var[band] / model_var) / chi2_median)
            rospy.loginfo(
                "z %.1f-%.1f m: %d pixels, model sigma_z %.4f m, measured / model %.3f (pooled %.3f)",
                lo,
                lo + 0.1,
                band.sum(),
                np.sqrt(model_var.mean()),
                ratio,
                np.sqrt(var[band].mean() / model_var.mean()),
            )
            checked.append((lo, ratio))
        self.assertGreaterEqual(len(checked), 3, "range bands with 2000 pixels: %s" % checked)
        for lo, ratio in checked:
            self.assertAlmostEqual(ratio, 1.0, delta=0.10, msg="sigma_z at %.1f m: ratio %.3f" % (lo, ratio))


if __name__ == "__main__":
    rostest.rosrun("cotton_harvester_sim", "cotton_world_sensors", CottonWorldSensorsTest)
