#!/usr/bin/python3
"""serial_L recovers by itself from a missing port, an unplugged port and a silent device."""
import os
import signal
import time
import unittest

import roslaunch
import rospy
import rostest
from roslaunch.core import Node

from serial_test_support import ActiveSettings, Watcher, seed_values
from waiting import seconds_until, wait_for

RECOVERY_LIMIT_S = 2.0


class SerialRecoveryTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('serial_recovery_test')
        cls.seed = seed_values(rospy.get_param('~seed_file'))
        cls.link = rospy.get_param('~link')
        cls.watch = Watcher()
        cls.stored = ActiveSettings()
        cls.stored.publish(cls.seed)
        cls.launch = roslaunch.scriptapi.ROSLaunch()
        cls.launch.start()
        cls.sim = None
        cls.watch.listen()  # serial_L's first warning must be heard
        cls.serial = cls.launch.launch(Node(
            'robopuppet', 'serial_interface', name='serial_L', namespace='/',
            args='_arm_side:=L _port_name:=%s _comm_rate:=50.0' % cls.link))

    @classmethod
    def tearDownClass(cls):
        if cls.sim is not None:
            cls.sim.stop()
        cls.serial.stop()
        cls.launch.stop()

    def start_sim(self):
        """Start puppet_sim_L; return the seconds from its link appearing to serial_L holding
        the reloaded settings with joint states flowing again (None if that never happens)."""
        with self.watch.lock:
            self.watch.device_config = None  # the fresh device must be seen with the settings
        node = Node('robopuppet', 'puppet_sim', name='puppet_sim_L', namespace='/',
                    args='_arm_side:=L _state_rate:=50.0 _port_link:=%s' % self.link)
        type(self).sim = self.launch.launch(node)
        self.assertTrue(wait_for(lambda: os.path.lexists(self.link), 20.0, 0.005),
                        'puppet_sim did not create %s' % self.link)
        appeared = time.monotonic()

        def recovered():
            with self.watch.lock:
                loaded = self.watch.device_config == self.seed
            return loaded and len(self.watch.states_since(appeared)) >= 3
        if seconds_until(recovered, 10.0, 0.01) is None:
            return None
        took = time.monotonic() - appeared
        rospy.loginfo('serial_L recovered %.2f s after the port appeared', took)
        return took

    def wait_link_down_for(self, statuses):
        """Wait until serial_L has said 'link down' in this many more statuses (1 Hz): it kept
        retrying the port (every 0.5 s) all that time."""
        since = time.monotonic()
        self.assertTrue(wait_for(lambda: self.watch.diagnostics_since(since) >= statuses
                                      and self.watch.diagnostics.get('link') == 'down',
                                      statuses + 5.0), self.watch.diagnostics)

    def test_1_missing_port_is_logged_once_then_found(self):
        self.assertTrue(wait_for(
            lambda: self.watch.warnings_with('cannot open serial port'), 10.0))
        self.wait_link_down_for(3)
        self.assertEqual(len(self.watch.warnings_with('cannot open serial port')), 1,
                         self.watch.warnings)
        took = self.start_sim()
        self.assertIsNotNone(took, 'serial_L never loaded the settings')
        self.assertLess(took, RECOVERY_LIMIT_S)
        self.assertTrue(wait_for(lambda: self.watch.diagnostics.get('link') == 'up', 3.0))

    def test_2_unplug_and_replug(self):
        self.assertTrue(wait_for(lambda: self.watch.device_config == self.seed, 10.0))
        lost_before = len(self.watch.warnings_with('lost'))
        self.sim.stop()
        type(self).sim = None
        self.assertFalse(os.path.lexists(self.link))
        self.assertTrue(wait_for(
            lambda: len(self.watch.warnings_with('lost')) == lost_before + 1, 5.0))
        self.wait_link_down_for(3)
        self.assertEqual(len(self.watch.warnings_with('lost')), lost_before + 1,
                         self.watch.warnings)
        self.assertEqual(len(self.watch.warnings_with('cannot open serial port')), 1,
                         self.watch.warnings)
        took = self.start_sim()
        self.assertIsNotNone(took, 'serial_L never reloaded the settings after the replug')
        self.assertLess(took, RECOVERY_LIMIT_S)

    def test_3_silent_device(self):
        self.assertTrue(wait_for(lambda: self.watch.device_config == self.seed, 10.0))
        pid = self.sim.get_info()['pid']
        os.kill(pid, signal.SIGSTOP)  # the device stops talking; its port stays
        try:
            self.assertTrue(wait_for(lambda: self.watch.warnings_with('no frame from'), 6.0))
            # It re-opens the port every second: three more re-opens, one warning.
            reopens = int(self.watch.diagnostics['connects'])
            self.assertTrue(wait_for(
                lambda: int(self.watch.diagnostics['connects']) >= reopens + 3, 8.0),
                self.watch.diagnostics)
            self.assertEqual(len(self.watch.warnings_with('no frame from')), 1,
                             self.watch.warnings)
            diagnostics = self.watch.diagnostics
            self.assertEqual((diagnostics['message'], diagnostics['settings loaded']),
                             ('device silent', 'False'))
        finally:
            os.kill(pid, signal.SIGCONT)
        resumed = time.monotonic()
        self.assertTrue(wait_for(lambda: len(self.watch.states_since(resumed)) >= 3, 5.0))
        # Reloaded (the device may have restarted), and healthy again.
        self.assertTrue(wait_for(
            lambda: self.watch.diagnostics['settings loaded'] == 'True'
            and self.watch.diagnostics['level'] == 0, 5.0), self.watch.diagnostics)


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'serial_recovery', SerialRecoveryTest)
