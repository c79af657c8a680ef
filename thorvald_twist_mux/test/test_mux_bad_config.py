#!/usr/bin/python3
"""A misconfigured twist_mux exits non-zero at start-up and says which entry and key are wrong."""
import subprocess
import unittest

import rospy
import rostest
from roslib.packages import find_node

CASES = {
    'missing_key': "topics[0] (nav): missing key 'timeout'",
    'negative_timeout': 'topics[0] (nav): timeout is -1, expected a finite number >= 0',
    'duplicate_name': 'topics[1] (nav): duplicate name',
    'duplicate_lock': 'locks[1] (stop): duplicate name',
    'priority_range': 'priority is 300, expected an integer in 0..255',
    'bad_rate': '/bad_rate: parameter ~check_rate: found the number 0, expected a number in (0, 1000] [Hz]',
    'bad_flag': "/bad_flag: parameter ~zero_on_loss: found the string 'maybe', expected true or false",
    'no_topics': '/no_topics/topics is missing',
}


class MuxBadConfig(unittest.TestCase):
    def test_bad_configs(self):
        exe = find_node('thorvald_twist_mux', 'twist_mux')[0]
        for name, expected in CASES.items():
            with self.subTest(config=name):
                proc = subprocess.run([exe, '__name:=%s' % name], capture_output=True, text=True, timeout=20)
                self.assertEqual(proc.returncode, 1, proc.stdout + proc.stderr)
                self.assertIn(expected, proc.stdout + proc.stderr)


if __name__ == '__main__':
    rospy.init_node('test_mux_bad_config')
    rostest.rosrun('thorvald_twist_mux', 'mux_bad_config', MuxBadConfig)
