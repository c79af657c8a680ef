"""Waiting for conditions and keeping a topic's messages."""
import threading
import time


def _shutting_down():
    try:
        import rospy
    except ImportError:
        return False
    return rospy.core.is_initialized() and rospy.is_shutdown()


def wait_for(predicate, timeout, what, period=0.01):
    """Polls `predicate` every `period` seconds until it returns true; raises AssertionError naming `what` when
    `timeout` wall-clock seconds pass first (or ROS shuts down). Returns the predicate's last value."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() >= deadline or _shutting_down():
            raise AssertionError("timed out after %.1f s waiting for %s" % (timeout, what))
        time.sleep(period)


class Recorder:
    """Subscribes to `topic` and keeps every message (thread-safe). Extra keyword arguments go to the
    subscriber (e.g. queue_size)."""

    def __init__(self, topic, cls, **kwargs):
        import rospy

        self._lock = threading.Lock()
        self._msgs = []
        kwargs.setdefault("queue_size", 100)
        self.sub = rospy.Subscriber(topic, cls, self._on, **kwargs)

    def _on(self, msg):
        with self._lock:
            self._msgs.append(msg)

    def count(self):
        with self._lock:
            return len(self._msgs)

    def last(self):
        """The latest message, or None before the first."""
        with self._lock:
            return self._msgs[-1] if self._msgs else None

    def since(self, index):
        """The messages received from the `index`-th on (0 = all)."""
        with self._lock:
            return list(self._msgs[index:])

    def wait_count(self, n, timeout=5.0):
        """Waits until at least `n` messages arrived; returns the latest."""
        wait_for(lambda: self.count() >= n, timeout, "%d messages on %s" % (n, self.sub.resolved_name))
        return self.last()


class Latest:
    """Subscribes to `topic` and keeps only the latest message (`msg`, None before the first) and how many came
    (`count`): for fast or large topics a test only samples."""

    def __init__(self, topic, cls, queue_size=5):
        import rospy

        self.msg = None
        self.count = 0
        self.sub = rospy.Subscriber(topic, cls, self._on, queue_size=queue_size)

    def _on(self, msg):
        self.msg = msg
        self.count += 1
