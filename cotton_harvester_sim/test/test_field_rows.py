#!/usr/bin/python3
"""mujoco_harvest experiment:=field_rows drives a short field: a progress line per leg, every row completed and every
row-end turn entering the next row, the figures on harvest/metrics."""
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticStatus
from std_msgs.msg import String


class FieldRowsTest(unittest.TestCase):
    def test_field(self):
        rospy.init_node("test_field_rows")
        timeout = rospy.get_param("~timeout_s")
        rows = rospy.get_param("~rows")
        max_cross_track = rospy.get_param("~max_cross_track_rms_m")
        lock = threading.Lock()
        seen = {"metrics": None, "progress": []}

        def on_progress(msg):
            with lock:
                seen["progress"].append(msg.data)

        def on_metrics(msg):
            with lock:
                seen["metrics"] = msg

        rospy.Subscriber("harvest/field_progress", String, on_progress, queue_size=100)
        rospy.Subscriber("harvest/metrics", DiagnosticStatus, on_metrics, queue_size=10)
        deadline = time.time() + timeout
        while time.time() < deadline and not rospy.is_shutdown():
            with lock:
                if seen["metrics"] is not None:
                    break
            time.sleep(0.2)
        with lock:
            metrics, progress = seen["metrics"], list(seen["progress"])
        self.assertIsNotNone(metrics, "no harvest/metrics within %.0f s" % timeout)
        self.assertEqual(metrics.level, DiagnosticStatus.OK, metrics.message)
        values = {kv.key: float(kv.value) for kv in metrics.values}
        self.assertEqual(values["rows"], rows)
        self.assertEqual(values["rows_completed_pct"], 100.0)
        self.assertEqual(values["row_end_turn_success_pct"], 100.0)
        self.assertLessEqual(values["cross_track_rms_m"], max_cross_track)
        # Every leg (rows and turns) started and finished: 2 lines per leg.
        self.assertEqual(len([p for p in progress if p.endswith("done row %d" % (rows - 1))]), 1, progress)
        self.assertEqual(len([p for p in progress if "turn after row" in p]), 2 * (rows - 1), progress)


if __name__ == "__main__":
    rostest.rosrun("cotton_harvester_sim", "test_field_rows", FieldRowsTest)
