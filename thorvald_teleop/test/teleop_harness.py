"""Shared pieces of the thorvald_teleop rostests: the workspace's test helpers and a Twist as a tuple."""
from thorvald_testing import Recorder, wait_for  # noqa: F401 (re-exported for the tests)


def twist_tuple(t):
    return (t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z)
