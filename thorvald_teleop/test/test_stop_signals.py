#!/usr/bin/python3
"""Every node stops on SIGINT and on SIGTERM within STOP_DEADLINE seconds, exit code 0, in each state:

- `dead_master`: ROS_MASTER_URI names a port where nothing listens (roscpp retries the master for ever);
- `silent_master`: a port that accepts connections and never answers;
- `running`: registered with the test's master and spinning.

The nodes to check come from the private parameter `~nodes`: a list of {package, type, params (private
parameters set on the master for the running state)}. Each node runs on a pseudo-terminal (keyboard_teleop needs
one); in the running state the terminal must be back in canonical mode after the exit.
"""
import os
import signal
import socket
import time
import unittest

import rosgraph
import rospy
import rostest
from roslib.packages import find_node
from thorvald_testing import PtyProcess, wait_for

STOP_DEADLINE = 1.0    # [s] from the signal to the process's exit
START_DEADLINE = 30.0  # [s] for a node to reach the state under test on a loaded machine


def start_node(exe, name, master_uri):
    """One node process on a pty (kept open here to read its mode), its output collected."""
    return PtyProcess([exe, '__name:=%s' % name], env={'ROS_MASTER_URI': master_uri}, keep_slave=True)


class StopSignals(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.nodes = rospy.get_param('~nodes')
        for spec in cls.nodes:  # resolved once: rospack crawls the workspace on every lookup
            found = find_node(spec['package'], spec['type'])
            if not found:
                raise AssertionError('node %s/%s not found' % (spec['package'], spec['type']))
            spec['exe'] = found[0]
        cls.master = rosgraph.Master('/test_stop_signals')
        # Bound but not listening: connections are refused.
        cls.dead = socket.socket()
        cls.dead.bind(('127.0.0.1', 0))
        # Listening, never accepting: connections hang.
        cls.silent = socket.socket()
        cls.silent.bind(('127.0.0.1', 0))
        cls.silent.listen(64)

    @classmethod
    def tearDownClass(cls):
        cls.dead.close()
        cls.silent.close()

    def check(self, state, sig):
        failures = []
        for i, spec in enumerate(self.nodes):
            name = 'stop_%s_%s_%d' % (state, sig.name.lower(), i)
            what = '%s/%s (%s, %s)' % (spec['package'], spec['type'], state, sig.name)
            if state == 'running':
                for key, value in spec.get('params', {}).items():
                    rospy.set_param('/%s/%s' % (name, key), value)
                uri = os.environ['ROS_MASTER_URI']
            else:
                sock = self.dead if state == 'dead_master' else self.silent
                uri = 'http://127.0.0.1:%d' % sock.getsockname()[1]
            node = start_node(spec['exe'], name, uri)
            try:
                if state == 'running':
                    wait_for(lambda: self.registered(name), START_DEADLINE, '%s to register' % what)
                    wait_for(lambda: spec.get('ready_text', '') in node.text(), START_DEADLINE,
                             '%s to print %r' % (what, spec.get('ready_text', '')))
                elif state == 'dead_master':
                    wait_for(lambda: 'Failed to contact master' in node.text(), START_DEADLINE,
                             '%s to report the unreachable master' % what)
                else:
                    # Nothing is printed while a request hangs: give it time to be inside one.
                    started = time.monotonic()
                    wait_for(lambda: time.monotonic() - started > 2.0 or node.proc.poll() is not None, 5.0,
                             '%s to start' % what)
                    if node.proc.poll() is not None:
                        failures.append('%s exited by itself with %s before the signal' % (what, node.proc.poll()))
                        continue
                code, seconds = node.stop(sig, timeout=STOP_DEADLINE + 4.0)
                if code is None:
                    failures.append('%s still running %.0f s after the signal' % (what, STOP_DEADLINE + 4.0))
                elif seconds > STOP_DEADLINE:
                    failures.append('%s took %.2f s to stop' % (what, seconds))
                elif code != 0:
                    failures.append('%s exited with %d; output:\n%s' % (what, code, node.text()[-600:]))
                elif state == 'running' and not node.canonical():
                    failures.append('%s left the terminal in raw mode' % what)
            finally:
                node.close()
        self.assertEqual(failures, [])

    def registered(self, name):
        try:
            self.master.lookupNode('/' + name)
            return True
        except Exception:  # rosgraph raises MasterError until the node is known
            return False

    def test_dead_master_sigint(self):
        self.check('dead_master', signal.SIGINT)

    def test_dead_master_sigterm(self):
        self.check('dead_master', signal.SIGTERM)

    def test_silent_master_sigint(self):
        self.check('silent_master', signal.SIGINT)

    def test_silent_master_sigterm(self):
        self.check('silent_master', signal.SIGTERM)

    def test_running_sigint(self):
        self.check('running', signal.SIGINT)

    def test_running_sigterm(self):
        self.check('running', signal.SIGTERM)


if __name__ == '__main__':
    rospy.init_node('test_stop_signals')
    rostest.rosrun('thorvald_teleop', 'stop_signals', StopSignals)
