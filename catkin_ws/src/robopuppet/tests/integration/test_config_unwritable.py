#!/usr/bin/python3
"""rostest: the real config node on a damaged, uncreatable, read-only or full file system: it
repairs once, and otherwise keeps serving get_config and stored_settings and refuses every
change, from set_config and from the joint topics alike."""
import os
import shutil
import tempfile
import unittest

import roslaunch
import rospy
import rostest
from std_msgs.msg import Float32

from config_testing import (FIXTURE, ConfigNodeRunner, StoredSettings, joint_values,
                            set_config)
from tmpfs_testing import tmpfs
from robopuppet import interface, settings
from robopuppet.config import config_store

# Torn lines, an unknown and a repeated section, a repeated option, out-of-bound values.
DAMAGED = open(FIXTURE).read().replace(
    '[joint_4]', '[bogus]\npid_kp = 5\n[joint_4]', 1).replace(
    '[joint_5]\n', '[joint_5]\nvoltage_max = 1e20\npid_kp = 3.4e38\n', 1) + \
    '[joint_2]\npid_kp = 99\npid_\n'


class ConfigUnwritableTest(ConfigNodeRunner, unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='robopuppet-config-')
        self.launch = roslaunch.scriptapi.ROSLaunch()
        self.launch.start()
        self.process = None
        self.log_file = None
        self.publishers = []
        self.stored = StoredSettings()

    def tearDown(self):
        self.stored.unregister()
        for pub in self.publishers:
            pub.unregister()  # a latched change must not reach the next test's node
        if self.process is not None:
            self.stop_node()
        self.launch.stop()
        shutil.rmtree(self.dir)

    def get(self, proxy, joint):
        response = proxy(joint)
        return {name: getattr(response, name) for name in settings.NAMES}

    def publish(self, joint, name, value):
        pub = rospy.Publisher(interface.joint_topic('R', joint, name), Float32,
                              queue_size=1, latch=True)
        pub.publish(Float32(value))
        self.publishers.append(pub)

    def assert_serves_and_refuses(self, proxy, expected, reason):
        """get_config and stored_settings hold `expected`; a change is refused loudly, naming
        `reason`, and changes nothing."""
        self.wait_log('ERROR', 'CHANGES WILL NOT PERSIST')
        for joint in settings.JOINTS:
            self.assertEqual(self.get(proxy, joint), expected[joint])
        start = self.stored.wait(0)
        self.assertIsNotNone(start, 'stored_settings is published at start, also when unwritable')
        self.assertEqual([joint_values(j) for j in start.joints],
                         [expected[j] for j in settings.JOINTS])
        response = set_config(3, pid_kd=0.75)
        self.assertFalse(response.stored)
        self.assertIn('changes will not persist', response.error)
        self.assertIn(reason, response.error)
        self.assertEqual(joint_values(response.settings), expected[3])
        self.publish(3, 'pid_kd', 0.75)
        refusal = self.wait_log('ERROR', 'refused joint 3 pid_kd = 0.75')
        self.assertIn('changes will not persist', refusal[0])
        self.assertEqual(self.get(proxy, 3), expected[3], 'the refused change is not served')
        self.assertEqual([m.revision for m in self.stored.messages()], [0])

    def test_damaged_file_is_repaired_once_and_out_of_bound_values_are_named(self):
        path = os.path.join(self.dir, 'arm_R.ini')
        with open(path, 'w') as out:
            out.write(DAMAGED)
        expected, _ = config_store.parse(DAMAGED)
        proxy = self.start_node(path)
        self.wait_log('WARNING', '[joint_5] voltage_max = 1e20: invalid (outside its bound '
                                '[-7.2, 7.2] V')
        self.assertEqual(self.get(proxy, 5), expected[5])
        self.assertEqual(self.get(proxy, 5)['pid_kp'], 0.0, 'pid_kp 3.4e38 repaired to default')
        repaired = open(path).read()
        self.stop_node()
        proxy = self.start_node(path)
        self.wait_log('INFO', 'serving /puppet/arm_R/get_config')
        self.assertEqual(self.get(proxy, 2), expected[2])
        self.assertEqual(open(path).read(), repaired, 'the second start repairs nothing')
        self.assertEqual([msg for lvl, msg in self.logs() if lvl != 'INFO'], [])
        backups = [name for name in os.listdir(self.dir) if '.bak-' in name]
        self.assertEqual(len(backups), 1, backups)
        self.assertEqual(open(os.path.join(self.dir, backups[0])).read(), DAMAGED)

    def test_cannot_create(self):
        """Works as root without a mount: the live file's parent is a regular file."""
        blocker = os.path.join(self.dir, 'not_a_dir')
        open(blocker, 'w').close()
        proxy = self.start_node(os.path.join(blocker, 'arm_R.ini'))
        expected, _ = config_store.parse(open(FIXTURE).read())
        self.assert_serves_and_refuses(proxy, expected, 'cannot create')
        self.assertEqual(os.listdir(self.dir), ['not_a_dir'])

    def test_read_only_directory(self):
        with tmpfs(64, {'arm_R.ini': DAMAGED}, read_only=True) as disk:
            proxy = self.start_node(os.path.join(disk, 'arm_R.ini'))
            self.wait_log('ERROR', 'Read-only file system')
            self.assert_serves_and_refuses(proxy, config_store.parse(DAMAGED)[0],
                                           'Read-only file system')
            self.assertEqual(os.listdir(disk), ['arm_R.ini'])
            self.stop_node()

    def test_full_disk(self):
        with tmpfs(64, {'arm_R.ini': DAMAGED}, full=True) as disk:
            proxy = self.start_node(os.path.join(disk, 'arm_R.ini'))
            self.wait_log('ERROR', 'No space left on device')
            self.assert_serves_and_refuses(proxy, config_store.parse(DAMAGED)[0],
                                           'No space left on device')
            self.assertEqual(sorted(os.listdir(disk)), ['arm_R.ini', 'filler'],
                             'no empty backup, no temporary')
            self.assertEqual(open(os.path.join(disk, 'arm_R.ini')).read(), DAMAGED)
            self.stop_node()


if __name__ == '__main__':
    rospy.init_node('test_config_unwritable')
    rostest.rosrun('robopuppet', 'config_unwritable', ConfigUnwritableTest)
