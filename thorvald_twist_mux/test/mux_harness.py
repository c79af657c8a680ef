"""Shared pieces of the twist_mux rostests: publishers per input, a recorder of the output, waits with deadlines."""
import threading
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import Twist, TwistStamped
from std_msgs.msg import Bool, String


def twist(x):
    t = Twist()
    t.linear.x = x
    return t


class MuxHarness:
    def __init__(self, inputs, locks, out_topic='cmd_vel_out', node='twist_mux', out_stamped=False,
                 stamped_inputs=()):
        self.lock = threading.RLock()
        self.outputs = []  # (wall time [s], message)
        self.status = {'active': None, 'engaged_locks': None}
        self.diag = {}
        self.node = node
        self.pubs = {}
        self.sent = {}
        for name, topic in inputs.items():
            cls = TwistStamped if name in stamped_inputs else Twist
            self.pubs[name] = rospy.Publisher(topic, cls, queue_size=10)
        for name, topic in locks.items():
            self.pubs[name] = rospy.Publisher(topic, Bool, queue_size=10)
        self.out_sub = rospy.Subscriber(out_topic, TwistStamped if out_stamped else Twist, self._on_out,
                                        tcp_nodelay=True)
        self.subs = [rospy.Subscriber('%s/%s' % (node, key), String, self._on_status, key)
                     for key in self.status]
        self.subs.append(rospy.Subscriber('/diagnostics', DiagnosticArray, self._on_diag))
        self.wait_for(lambda: all(p.get_num_connections() > 0 for p in self.pubs.values())
                      and self.out_sub.get_num_connections() > 0, 15.0, 'connections to the mux')

    def _on_out(self, msg):
        with self.lock:
            self.outputs.append((time.monotonic(), msg))

    def _on_status(self, msg, key):
        with self.lock:
            self.status[key] = msg.data

    def _on_diag(self, msg):
        with self.lock:
            for s in msg.status:
                self.diag[s.name] = (s.level, s.message, {kv.key: kv.value for kv in s.values})

    def wait_for(self, predicate, timeout, what):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and not rospy.is_shutdown():
            with self.lock:
                if predicate():
                    return
            time.sleep(0.005)  # polling interval of the wait, not a synchronisation delay
        raise AssertionError('timed out after %.1f s waiting for %s' % (timeout, what))

    def publish(self, name, value):
        self.sent[name] = self.sent.get(name, 0) + 1
        self.pubs[name].publish(value if not isinstance(value, float) else twist(value))

    def output_values(self):
        with self.lock:
            return [round((m.twist if hasattr(m, 'twist') else m).linear.x, 6) for _, m in self.outputs]

    def wait_output(self, value, timeout=5.0):
        self.wait_for(lambda: value in [round((m.twist if hasattr(m, 'twist') else m).linear.x, 6)
                                        for _, m in self.outputs], timeout, 'output %s' % value)
        with self.lock:
            return [t for t, m in self.outputs
                    if round((m.twist if hasattr(m, 'twist') else m).linear.x, 6) == value][0]

    def received(self, kind, name):
        entry = self.diag.get('%s: %s %s' % (self.node, kind, name))
        return int(entry[2]['received' if kind == 'input' else 'messages']) if entry else -1

    def wait_received(self, name, timeout=5.0):
        """Waits until the mux's diagnostics say input `name` has received every message published on it."""
        count = self.sent.get(name, 0)
        self.wait_for(lambda: self.received('input', name) >= count, timeout,
                      'diagnostics: input %s received %d' % (name, count))

    def wait_status(self, key, value, timeout=5.0):
        self.wait_for(lambda: self.status[key] == value, timeout, 'status %s == %r' % (key, value))

    def publish_until_output(self, name, value, timeout=5.0, period=0.02):
        """Publishes `value` (a float or a message) on `name` every `period` until it comes out; returns the time it
        came out."""
        x = value if isinstance(value, float) else value.twist.linear.x
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and not rospy.is_shutdown():
            self.publish(name, value)
            try:
                return self.wait_output(x, period)
            except AssertionError:
                pass
        raise AssertionError('input %s value %s never came out' % (name, value))


class Heartbeat:
    """Publishes Bool false on a lock topic at a fixed rate until stopped (a healthy watchdog publisher)."""

    def __init__(self, pub, period=0.05):
        self.pub = pub
        self.period = period
        self.last = None
        self.running = True
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        while self.running and not rospy.is_shutdown():
            self.last = time.monotonic()  # before publishing: the mux's stamp of this beat is later
            self.pub.publish(Bool(False))
            time.sleep(self.period)  # publishing rate of the heartbeat

    def stop(self):
        self.running = False
        self.thread.join()
