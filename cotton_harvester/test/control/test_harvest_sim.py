#!/usr/bin/python3
"""The harvest machine drives the simulated rover and arm through the serial path and picks bolls."""
import os
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticStatus
from std_msgs.msg import Int32
from thorvald_state_machine.msg import MachineStatus


class HarvestSimTest(unittest.TestCase):
    def test_harvest_runs_to_the_row_end(self):
        rospy.init_node("test_harvest_sim")
        csv = rospy.get_param("~csv")
        if os.path.exists(csv):
            os.remove(csv)  # the run takes minutes: its row is the only one written after this
        lock = threading.Lock()
        seen = {"status": None, "metrics": None, "remaining": None, "states": set()}

        def on_status(msg):
            with lock:
                seen["status"] = msg
                if msg.active_state:
                    seen["states"].add(msg.active_state)

        def on_metrics(msg):
            with lock:
                seen["metrics"] = msg

        def on_remaining(msg):
            with lock:
                seen["remaining"] = msg.data

        rospy.Subscriber("harvest/machine_status", MachineStatus, on_status)
        rospy.Subscriber("harvest/metrics", DiagnosticStatus, on_metrics)
        rospy.Subscriber("sim/bolls_remaining", Int32, on_remaining)
        deadline = time.monotonic() + 220.0
        done = False
        while time.monotonic() < deadline and not rospy.is_shutdown():
            with lock:
                status = seen["status"]
                done = status is not None and not status.running and status.last_outcome in ("finished", "aborted")
            if done:
                break
            time.sleep(0.1)
        self.assertTrue(done, "the harvest did not end: %s" % seen["status"])
        # The final metrics: the next message published after the end.
        with lock:
            seen["metrics"] = None
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline and not rospy.is_shutdown():
            with lock:
                if seen["metrics"] is not None:
                    break
            time.sleep(0.05)
        with lock:
            status, metrics, remaining, states = seen["status"], seen["metrics"], seen["remaining"], seen["states"]
        # The metrics' message says why the machine aborted ("ended: aborted: ..."); the last transitions where.
        why = metrics.message if metrics is not None else "no harvest/metrics after the end"
        path = ", ".join("%s [%s] %s" % (t.state, t.outcome, t.next) for t in status.history[-6:])
        self.assertEqual(status.last_outcome, "finished", "%s; last transitions: %s" % (why, path))
        self.assertIn("OBSERVE", states)
        self.assertIn("PICK", states)
        self.assertIsNotNone(metrics, "no harvest/metrics after the end")
        values = {kv.key: kv.value for kv in metrics.values}
        picked = int(values["picked"])
        self.assertGreaterEqual(picked, 1)
        self.assertEqual(int(values["bolls_present"]), 2)
        # The simulated row agrees: what the machine counts as picked is gone from the plants.
        self.assertIsNotNone(remaining)
        self.assertLessEqual(picked, 2 - remaining)
        self.assertGreater(float(values["time_s"]), 0.0)
        # The CSV row is appended when the run ends, independently of the metrics topic: wait for it (deadline).
        lines = []
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline and not rospy.is_shutdown():
            if os.path.exists(csv):
                with open(csv) as f:
                    lines = [line.strip() for line in f if line.strip()]
                if len(lines) >= 2:
                    break
            time.sleep(0.05)
        self.assertGreaterEqual(len(lines), 2, "no metrics row in %s" % csv)
        self.assertTrue(lines[0].startswith("run,bolls_present,detected,reached,picked"))
        row = lines[-1].split(",")
        self.assertEqual(int(row[4]), picked)


if __name__ == "__main__":
    rostest.rosrun("cotton_harvester", "harvest_sim", HarvestSimTest)
