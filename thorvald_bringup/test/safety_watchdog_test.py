#!/usr/bin/python3
"""The fail-safe safety lock of a Thorvald robot: twist_mux's safety_watchdog lock on safety/heartbeat, kept
released by safety_heartbeat while its safety source (here a bumper) is heard and clear."""
import threading
import time
import unittest

import rosnode
import rospy
import rostest
from geometry_msgs.msg import Twist
from std_msgs.msg import Bool, String


class SafetyWatchdog(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.engaged = None
        self.last_out = None
        rospy.Subscriber('/r1/twist_mux/engaged_locks', String, self.on_locks)
        rospy.Subscriber('/r1/twist_mux/cmd_vel', Twist, self.on_out)
        self.nav = rospy.Publisher('/r1/nav_vel', Twist, queue_size=1)
        self.bumper = rospy.Publisher('/r1/bumper', Bool, queue_size=1)
        self.bumper_value = False
        self.bumper_alive = True
        self.stop = False
        self.feeder = threading.Thread(target=self.feed)
        self.feeder.start()

    def tearDown(self):
        self.stop = True
        self.feeder.join()

    def on_locks(self, msg):
        with self.lock:
            self.engaged = msg.data

    def on_out(self, msg):
        with self.lock:
            self.last_out = (time.monotonic(), msg.linear.x)

    def feed(self):
        """nav_vel at 20 Hz (the driving input) and the bumper at 20 Hz while it is alive."""
        while not self.stop and not rospy.is_shutdown():
            t = Twist()
            t.linear.x = 0.5
            self.nav.publish(t)
            if self.bumper_alive:
                self.bumper.publish(Bool(data=self.bumper_value))
            time.sleep(0.05)

    def wait_for(self, predicate, timeout, what):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            with self.lock:
                if predicate():
                    return time.monotonic()
            time.sleep(0.01)
        with self.lock:
            self.fail('timed out waiting for %s (engaged locks: %r)' % (what, self.engaged))

    def watchdog_engaged(self):
        return self.engaged is not None and 'safety_watchdog' in self.engaged.split(',')

    def driving(self):
        return self.last_out is not None and time.monotonic() - self.last_out[0] < 0.2 and self.last_out[1] > 0.4

    def test_lock_engages_when_its_source_or_the_heartbeat_goes_away(self):
        self.wait_for(lambda: self.engaged == '', 20.0, 'the watchdog lock to be released by the heartbeat')
        self.wait_for(self.driving, 5.0, 'nav_vel to drive')

        # The bumper asks for a stop.
        self.bumper_value = True
        self.wait_for(self.watchdog_engaged, 2.0, 'the lock to engage on the bumper')
        self.bumper_value = False
        self.wait_for(lambda: self.engaged == '', 2.0, 'the lock to release')
        self.wait_for(self.driving, 2.0, 'driving again')

        # The bumper falls silent: the heartbeat node engages the lock (0.3 s watch timeout).
        self.bumper_alive = False
        t0 = time.monotonic()
        t1 = self.wait_for(self.watchdog_engaged, 2.0, 'the lock to engage on a silent bumper')
        self.assertLess(t1 - t0, 1.0)
        self.bumper_alive = True
        self.wait_for(lambda: self.engaged == '', 2.0, 'the lock to release')

        # The heartbeat node dies: twist_mux engages the lock by itself (0.5 s lock timeout) and stops driving.
        killed, _ = rosnode.kill_nodes(['/r1/safety_heartbeat'])
        self.assertEqual(killed, ['/r1/safety_heartbeat'])
        t0 = time.monotonic()
        t1 = self.wait_for(self.watchdog_engaged, 3.0, 'the lock to engage with the heartbeat node dead')
        self.assertLess(t1 - t0, 1.5)
        time.sleep(0.3)
        with self.lock:
            self.assertFalse(self.driving(), 'twist_mux still passes nav_vel with the safety heartbeat dead')


if __name__ == '__main__':
    rospy.init_node('safety_watchdog_test')
    rostest.rosrun('thorvald_bringup', 'safety_watchdog', SafetyWatchdog)
