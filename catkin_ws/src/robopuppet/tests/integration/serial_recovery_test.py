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

from serial_test_support import TempConfig, Watcher, seed_values, wait_for

RECOVERY_LIMIT_S = 2.0


class SerialRecoveryTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('serial_recovery_test')
        seed_file = rospy.get_param('~seed_file')
        cls.seed = seed_values(seed_file)
        cls.link = rospy.get_param('~link')
        cls.watch = Watcher()
        cls.launch = roslaunch.scriptapi.ROSLaunch()
        cls.launch.start()
        cls.sim = None
        cls.config = TempConfig(cls.launch, seed_file)
        time.sleep(1.0)  # let the log subscription connect before serial_L's first warning
        cls.serial = cls.launch.launch(Node(
            'robopuppet', 'serial_interface', name='serial_L', namespace='/',
            args='_arm_side:=L _port_name:=%s' % cls.link))

    @classmethod
    def tearDownClass(cls):
        if cls.sim is not None:
            cls.sim.stop()
        cls.serial.stop()
        cls.config.stop()
        cls.launch.stop()

    def start_sim(self):
        """Start puppet_sim_L; return the seconds from its link appearing to serial_L holding
        the reloaded settings with joint states flowing again (None if that never happens)."""
        with self.watch.lock:
            self.watch.device_config = None  # the fresh device must be seen with the settings
        node = Node('robopuppet', 'puppet_sim', name='puppet_sim_L', namespace='/',
                    args='_arm_side:=L _state_rate:=50.0 _port_link:=%s' % self.link)
        type(self).sim = self.launch.launch(node)
        self.assertIsNotNone(wait_for(lambda: os.path.lexists(self.link), 20.0, 0.005),
                             'puppet_sim did not create %s' % self.link)
        appeared = time.monotonic()

        def recovered():
            with self.watch.lock:
                loaded = self.watch.device_config == self.seed
            return loaded and len(self.watch.states_since(appeared)) >= 3
        if wait_for(recovered, 10.0, 0.01) is None:
            return None
        took = time.monotonic() - appeared
        rospy.loginfo('serial_L recovered %.2f s after the port appeared', took)
        return took

    def warnings(self, text):
        with self.watch.lock:
            return [w for w in self.watch.warnings if text in w]

    def test_1_missing_port_is_logged_once_then_found(self):
        time.sleep(3.5)  # serial_L retries about once a second meanwhile
        self.assertEqual(len(self.warnings('cannot open serial port')), 1, self.watch.warnings)
        self.assertEqual(self.watch.diagnostics.get('link'), 'down')
        took = self.start_sim()
        self.assertIsNotNone(took, 'serial_L never loaded the settings')
        self.assertLess(took, RECOVERY_LIMIT_S)
        self.assertIsNotNone(wait_for(lambda: self.watch.diagnostics.get('link') == 'up', 3.0))

    def test_2_unplug_and_replug(self):
        self.assertIsNotNone(wait_for(lambda: self.watch.device_config == self.seed, 10.0))
        lost_before = len(self.warnings('lost'))
        self.sim.stop()
        type(self).sim = None
        self.assertFalse(os.path.lexists(self.link))
        self.assertIsNotNone(wait_for(lambda: self.watch.diagnostics.get('link') == 'down', 3.0))
        time.sleep(3.0)
        self.assertEqual(len(self.warnings('lost')), lost_before + 1, self.watch.warnings)
        self.assertEqual(len(self.warnings('cannot open serial port')), 1, self.watch.warnings)
        took = self.start_sim()
        self.assertIsNotNone(took, 'serial_L never reloaded the settings after the replug')
        self.assertLess(took, RECOVERY_LIMIT_S)

    def test_3_silent_device(self):
        self.assertIsNotNone(wait_for(lambda: self.watch.device_config == self.seed, 10.0))
        connects = int(self.watch.diagnostics['connects'])
        pid = self.sim.get_info()['pid']
        os.kill(pid, signal.SIGSTOP)  # the device stops talking; its port stays
        try:
            self.assertIsNotNone(wait_for(lambda: self.warnings('no frame from'), 6.0))
            time.sleep(4.0)
            self.assertEqual(len(self.warnings('no frame from')), 1, self.watch.warnings)
        finally:
            os.kill(pid, signal.SIGCONT)
        resumed = time.monotonic()
        self.assertIsNotNone(wait_for(lambda: len(self.watch.states_since(resumed)) >= 3, 5.0))
        self.assertIsNotNone(wait_for(
            lambda: int(self.watch.diagnostics['connects']) > connects
            and self.watch.diagnostics['settings loaded'] == 'True'
            and self.watch.diagnostics['level'] == 0, 5.0), self.watch.diagnostics)


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'serial_recovery', SerialRecoveryTest)
