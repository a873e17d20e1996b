#!/usr/bin/python3
"""rostest: the diagnostic aggregator puts each RoboPuppet status in its RoboPuppet group."""
import threading
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray

from robopuppet import interface

# The aggregated name of each status arm.launch's nodes publish for arm R, by group.
EXPECTED = {'RoboPuppet/Puppet serial link': '/serial_R: ' + interface.DIAG_LINK,
            'RoboPuppet/Teleoperation': 'arm_R: ' + interface.DIAG_TELEOP,
            'RoboPuppet/Operator-robot link': 'arm_R: ' + interface.DIAG_NETWORK}


class AggregatorTest(unittest.TestCase):
    """Wait for one /diagnostics_agg that holds every expected status in its group."""

    def test_each_status_is_in_its_group(self):
        names, seen = set(), threading.Event()
        wanted = {'/%s/%s' % (group, status.lstrip('/')) for group, status in EXPECTED.items()}

        def on_agg(msg):
            names.clear()
            names.update(s.name for s in msg.status)
            if wanted <= names:
                seen.set()
        sub = rospy.Subscriber('/diagnostics_agg', DiagnosticArray, on_agg, queue_size=10)
        try:
            seen.wait(45.0)
        finally:
            sub.unregister()
        self.assertTrue(seen.is_set(), 'missing %s in %s' % (sorted(wanted - names), sorted(names)))
        others = [n for n in names if n.startswith('/Other/')]
        self.assertEqual(others, [], 'RoboPuppet statuses outside their groups')


if __name__ == '__main__':
    rospy.init_node('test_diagnostics')
    rostest.rosrun('robopuppet', 'test_diagnostics', AggregatorTest)
