"""Helpers shared by the workspace's Python rostests.

- `wait_for`: poll a condition until it holds or a wall-clock deadline passes (no fixed sleeps in tests).
- `Recorder`: every message of a topic, with the latest one and waits on the count.
- `Latest`: only the latest message of a topic and the count (fast or large topics).
- `run_until_line`: run a command, collect its output until a line contains a text, the command exits or a deadline
  passes, then stop it.
- `PtyProcess`: a process whose standard streams are a pseudo-terminal (for nodes that read a keyboard or act on
  terminal signals), its output collected in the background.
- `restore_default_signals`: `preexec_fn` for a test's own child processes, so that stopping them with a signal does
  not depend on how the test suite was started (in the background, SIGINT is ignored and children inherit that).
- `load_source`, `load_package_module`: a Python source file that is not an installed module (a bench's scorer in a
  package's folder) loaded as a module.
"""
from thorvald_testing.modules import load_package_module, load_source
from thorvald_testing.process import PtyProcess, restore_default_signals, run_until_line
from thorvald_testing.waiting import Latest, Recorder, wait_for

__all__ = ["Latest", "PtyProcess", "Recorder", "load_package_module", "load_source", "restore_default_signals",
           "run_until_line", "wait_for"]
