"""Shared pieces of the thorvald_teleop rostests: a recorder of one topic and waits with deadlines."""
import threading
import time

import rospy


def wait_for(predicate, timeout, what):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and not rospy.is_shutdown():
        if predicate():
            return
        time.sleep(0.005)  # polling interval of the wait, not a synchronisation delay
    raise AssertionError('timed out after %.1f s waiting for %s' % (timeout, what))


class Recorder:
    """Keeps every message of a topic with its arrival time (monotonic [s])."""

    def __init__(self, topic, cls, **kwargs):
        self.lock = threading.Lock()
        self.messages = []
        self.sub = rospy.Subscriber(topic, cls, self._on, **kwargs)

    def _on(self, msg):
        with self.lock:
            self.messages.append((time.monotonic(), msg))

    def count(self):
        with self.lock:
            return len(self.messages)

    def last(self):
        with self.lock:
            return self.messages[-1][1] if self.messages else None

    def since(self, index):
        with self.lock:
            return [m for _, m in self.messages[index:]]

    def wait_count(self, n, timeout=5.0):
        wait_for(lambda: self.count() >= n, timeout, '%d messages on %s' % (n, self.sub.name))


def twist_tuple(t):
    return (t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z)
