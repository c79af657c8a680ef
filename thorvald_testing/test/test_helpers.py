#!/usr/bin/python3
"""The shared test helpers against real processes and clocks (no ROS master needed)."""
import os
import signal
import sys
import tempfile
import time
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))
from thorvald_testing import PtyProcess, load_package_module, load_source, run_until_line, wait_for  # noqa: E402


class WaitFor(unittest.TestCase):
    def test_returns_the_value_once_true(self):
        start = time.monotonic()
        self.assertEqual(wait_for(lambda: time.monotonic() - start > 0.05 and "done", 2.0, "50 ms"), "done")

    def test_times_out_naming_the_condition(self):
        start = time.monotonic()
        with self.assertRaises(AssertionError) as raised:
            wait_for(lambda: False, 0.1, "the impossible")
        self.assertIn("the impossible", str(raised.exception))
        self.assertGreaterEqual(time.monotonic() - start, 0.1)
        self.assertLess(time.monotonic() - start, 1.0)


class RunUntilLine(unittest.TestCase):
    def test_exit_code_and_output_of_a_command_that_ends(self):
        code, out = run_until_line(["/bin/sh", "-c", "echo one; echo two >&2; exit 3"], deadline_s=10)
        self.assertEqual(code, 3)
        self.assertIn("one", out)
        self.assertIn("two", out)

    def test_stops_a_running_command_once_the_line_appears(self):
        start = time.monotonic()
        code, out = run_until_line(["/bin/sh", "-c", "echo ready; exec sleep 30"], wanted="ready", deadline_s=20)
        self.assertLess(time.monotonic() - start, 10)
        self.assertIn("ready", out)
        self.assertEqual(code, -signal.SIGINT)

    def test_stops_the_command_even_when_this_process_ignores_sigint(self):
        # A suite started in the background ignores SIGINT and its children inherit that: the helper must give the
        # command the default handling back, or the command would run on to the kill after stop_wait_s.
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            code, out = run_until_line(["/bin/sh", "-c", "echo ready; exec sleep 30"], wanted="ready", deadline_s=20,
                                       stop_wait_s=5)
        finally:
            signal.signal(signal.SIGINT, previous)
        self.assertIn("ready", out)
        self.assertEqual(code, -signal.SIGINT)

    def test_deadline_without_the_line_gives_no_exit_code(self):
        code, out = run_until_line(["/bin/sh", "-c", "echo busy; exec sleep 30"], wanted="never", deadline_s=0.5)
        self.assertIsNone(code)
        self.assertIn("busy", out)


class Pty(unittest.TestCase):
    def test_echoes_typed_text_and_stops_on_a_signal(self):
        proc = PtyProcess(["/bin/cat"], keep_slave=True)
        try:
            self.assertTrue(proc.canonical())
            proc.write(b"hello\n")
            wait_for(lambda: proc.text().count("hello") >= 2, 5.0, "cat's echo")  # the terminal's echo + cat
            code, seconds = proc.stop(signal.SIGTERM, timeout=5.0)
            self.assertEqual(code, -signal.SIGTERM)
            self.assertLess(seconds, 5.0)
        finally:
            proc.close()


class LoadModule(unittest.TestCase):
    def test_a_source_file_without_the_py_extension_is_a_fresh_module(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "a_bench")
            with open(path, "w") as f:
                f.write("COUNT = [0]\n\ndef answer():\n    COUNT[0] += 1\n    return 42\n")
            first = load_source(path)
            self.assertEqual(first.__name__, "a_bench")
            self.assertEqual(first.answer(), 42)
            second = load_source(path, name="other")
            self.assertEqual(second.__name__, "other")
            self.assertEqual(second.COUNT, [0], "each load runs the file afresh")
            self.assertNotIn("a_bench", sys.modules)

    def test_a_file_of_a_package_found_by_rospack(self):
        waiting = load_package_module("thorvald_testing", "src/thorvald_testing/waiting.py")
        self.assertTrue(callable(waiting.wait_for))


if __name__ == "__main__":
    import rosunit

    rosunit.unitrun("thorvald_testing", "test_helpers", "__main__")
