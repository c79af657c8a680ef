#!/usr/bin/python3
"""mujoco_harvest harvests a short row: its status shows every state it went through, every reachable boll is
picked by the simulated vacuum, the metrics are published and the CSV row is written."""
import os
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticStatus
from thorvald_state_machine.msg import MachineStatus


class HarvestMujocoTest(unittest.TestCase):
    def test_short_row(self):
        rospy.init_node("test_harvest_mujoco")
        csv = rospy.get_param("~metrics_csv")
        run_name = rospy.get_param("~run_name")
        timeout = rospy.get_param("~timeout_s")
        expected_states = set(rospy.get_param("~states"))
        # Bolls the vacuum must take; -1 (ideal): every reachable one. The datasheet world asks for a measured
        # floor instead (its misses and their causes: the package README).
        min_picked = rospy.get_param("~min_picked", -1)
        if os.path.exists(csv):
            os.remove(csv)  # the node writes its row at the end of the run, seconds from now
        lock = threading.Lock()
        seen = {"metrics": None, "states": set()}

        def on_status(msg):
            with lock:
                if msg.active_state:
                    seen["states"].add(msg.active_state)

        def on_metrics(msg):
            with lock:
                seen["metrics"] = msg

        rospy.Subscriber("harvest/machine_status", MachineStatus, on_status, queue_size=1000)
        rospy.Subscriber("harvest/metrics", DiagnosticStatus, on_metrics, queue_size=10)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and not rospy.is_shutdown():
            with lock:
                if seen["metrics"] is not None:
                    break
            time.sleep(0.1)  # polling a condition, with the deadline above
        with lock:
            metrics, states = seen["metrics"], set(seen["states"])
        self.assertIsNotNone(metrics, "no harvest/metrics within %.0f s" % timeout)
        values = {kv.key: float(kv.value) for kv in metrics.values}
        self.assertEqual(metrics.level, DiagnosticStatus.OK, metrics.message)
        self.assertEqual(metrics.message, "finished")
        self.assertEqual(values["bolls_present"], 6)
        self.assertGreaterEqual(values["bolls_reachable"], 5)
        if min_picked < 0:
            self.assertEqual(values["picked"], values["bolls_reachable"], values)
        else:
            self.assertGreaterEqual(values["picked"], min_picked, values)
        self.assertTrue(expected_states <= states, "states seen: %s" % sorted(states))
        # The CSV row is written after the metrics are published: wait for it too.
        row = None
        while time.monotonic() < deadline and row is None:
            if os.path.exists(csv):
                with open(csv) as f:
                    rows = [line.strip().split(",") for line in f if line.startswith(run_name + ",")]
                if rows:
                    row = rows[-1]
            if row is None:
                time.sleep(0.1)
        self.assertIsNotNone(row, "no row %s in %s" % (run_name, csv))
        self.assertEqual(int(row[4]), int(values["picked"]))


if __name__ == "__main__":
    rostest.rosrun("cotton_harvester_sim", "test_harvest_mujoco", HarvestMujocoTest)
