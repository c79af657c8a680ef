#!/usr/bin/env python3
"""Checks the headland map that greenhouse_mapping.launch's scripted drive saves in the MuJoCo greenhouse against the
world's truth: the rear and side walls must be found near where the truth puts them, the headland's width must be
right, the walls must be mapped along most of the headland, and nearly every occupied cell there must lie on one."""
import math
import os
import sys
import time
import unittest

import rospy
import rostest
import yaml


def read_pgm(path):
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:  # magic, width, height, maxval, with comments
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    assert fields[0] == b"P5", "not a binary PGM"
    w, h = int(fields[1]), int(fields[2])
    pixels = data[pos + 1:pos + 1 + w * h]
    assert len(pixels) == w * h, "PGM truncated"
    return w, h, pixels


class GreenhouseSimMapping(unittest.TestCase):
    def test_map_saved_with_walls_where_the_truth_has_them(self):
        stem = rospy.get_param("~map_file")
        truth_file = rospy.get_param("~truth_file")
        origin_x = rospy.get_param("~origin_x")
        tol = rospy.get_param("~tolerance")
        # A map left by an earlier run must not pass for this run's: only a map written after the test started counts
        # (the scripted drive saves it after about a minute of driving).
        started = time.time()
        deadline = started + 160.0

        def fresh():
            return os.path.exists(stem + ".yaml") and os.path.getmtime(stem + ".yaml") >= started

        while not fresh() and time.time() < deadline:
            time.sleep(0.5)
        self.assertTrue(fresh(), "the scripted drive's save_map did not write the map")
        time.sleep(1.0)  # the PGM is written with the YAML; let both be complete
        with open(stem + ".yaml") as f:
            meta = yaml.safe_load(f)
        with open(truth_file) as f:
            truth = yaml.safe_load(f)
        w, h, px = read_pgm(os.path.join(os.path.dirname(stem + ".yaml"), meta["image"]))
        res, ox, oy = meta["resolution"], meta["origin"][0], meta["origin"][1]
        occupied = []
        for row in range(h):
            for col in range(w):
                if px[row * w + col] < 50:  # map_server trinary: occupied is black
                    occupied.append((ox + (col + 0.5) * res, oy + (h - 1 - row + 0.5) * res))
        self.assertGreater(len(occupied), 100)
        rear_x = truth["walls"]["rear_x"] - origin_x
        side_y = truth["walls"]["side_y"]
        end_x = truth["walls"]["end_x"] - origin_x
        headland = [p for p in occupied if p[0] <= -origin_x + 1.0]  # the headland and 1 m into the rows

        # The map frame is where mapping started; the scan matcher may place the whole map a few centimetres off that
        # (a headland is a long corridor: along the rows only the rear wall holds it). Each wall is found near where
        # the truth puts it, then the map's shape is checked: headland width, straight walls, nothing off them.
        def wall_at(coord, expected, lo, hi):
            values = sorted(coord(p) for p in headland if abs(coord(p) - expected) <= search and lo <= other(p) <= hi)
            return values[len(values) // 2] if values else float("nan"), values

        search = 0.3
        other = lambda p: p[1]
        rear, rear_cells = wall_at(lambda p: p[0], rear_x, side_y[0] + 0.1, side_y[1] - 0.1)
        other = lambda p: p[0]
        right, right_cells = wall_at(lambda p: p[1], side_y[0], rear_x + 0.1, -origin_x)
        left, left_cells = wall_at(lambda p: p[1], side_y[1], rear_x + 0.1, -origin_x)
        print("map walls: rear %.3f (truth %.3f), right %.3f (%.3f), left %.3f (%.3f)" %
              (rear, rear_x, right, side_y[0], left, side_y[1]))
        for name, found, expected in (("rear", rear, rear_x), ("right", right, side_y[0]), ("left", left, side_y[1])):
            self.assertLess(abs(found - expected), 0.15, "%s wall %.3f m from where mapping started says" %
                            (name, found - expected))
        self.assertLess(abs((left - right) - (side_y[1] - side_y[0])), tol, "headland width")
        found = {"rear": (lambda p: abs(p[0] - rear)), "right": (lambda p: abs(p[1] - right)),
                 "left": (lambda p: abs(p[1] - left)), "end": (lambda p: abs(p[0] - end_x))}
        on_wall = sum(1 for p in headland if min(d(p) for d in found.values()) <= tol)
        print("on walls %.3f of %d cells" % (on_wall / float(len(headland)), len(headland)))
        self.assertGreater(on_wall / float(len(headland)), 0.95, "occupied cells off every wall on the headland")

        def coverage(dist, along, lo, hi):
            bins = set(int((along(p) - lo) / 0.1) for p in headland if dist(p) <= tol and lo <= along(p) <= hi)
            return len(bins) / max(1.0, (hi - lo) / 0.1)

        cover = {"rear": coverage(found["rear"], lambda p: p[1], side_y[0] + 0.1, side_y[1] - 0.1),
                 "right": coverage(found["right"], lambda p: p[0], rear_x + 0.1, -origin_x),
                 "left": coverage(found["left"], lambda p: p[0], rear_x + 0.1, -origin_x)}
        print("coverage %r" % cover)
        for name, c in cover.items():
            self.assertGreater(c, 0.8, "%s wall mapped along %.0f %% of the headland only" % (name, 100 * c))


if __name__ == "__main__":
    rospy.init_node("greenhouse_sim_mapping_test")
    rostest.rosrun("thorvald_bringup", "greenhouse_sim_mapping", GreenhouseSimMapping, sys.argv)
