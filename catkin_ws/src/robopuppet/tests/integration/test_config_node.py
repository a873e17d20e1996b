#!/usr/bin/python3
"""rostest: the real config node stores set_config requests all or none, publishes what it stores
on stored_settings, still takes the 2020 joint_J/<setting> topics, serves get_config as before,
refuses implausible values and survives a restart."""
import os
import shutil
import tempfile
import unittest

import roslaunch
import rospy
import rostest
from std_msgs.msg import Float32

from config_testing import (FIXTURE, ConfigNodeRunner, StoredSettings, joint_values,
                            set_config, wait_for)
from robopuppet import interface, settings
from robopuppet.config import config_store


class ConfigNodeTest(ConfigNodeRunner, unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='robopuppet-config-')
        self.path = os.path.join(self.dir, 'arm_R.ini')
        self.launch = roslaunch.scriptapi.ROSLaunch()
        self.launch.start()
        self.process = None
        self.expected, _ = config_store.parse(open(FIXTURE).read())
        self.stored = StoredSettings()

    def tearDown(self):
        self.stored.unregister()
        if self.process is not None:
            self.process.stop()
        self.launch.stop()
        shutil.rmtree(self.dir)

    def on_disk(self):
        with open(self.path) as ini:
            config, problems = config_store.parse(ini.read())
        self.assertEqual(problems, [])
        return config

    def wait_stored(self, revision):
        """Return the stored_settings message of `revision`; fail when none comes."""
        msg = self.stored.wait(revision)
        self.assertIsNotNone(msg, 'no stored_settings revision %d; got %r' % (
            revision, [m.revision for m in self.stored.messages()]))
        self.assertEqual([j.joint for j in msg.joints], list(settings.JOINTS))
        return msg

    def test_set_config_stores_all_or_none_and_publishes_each_change(self):
        proxy = self.start_node(self.path)
        start = self.wait_stored(0)
        self.assertEqual([joint_values(j) for j in start.joints],
                         [self.expected[j] for j in settings.JOINTS], 'latched at start')

        # A new minimum above the stored maximum, with its new maximum, in one request.
        response = set_config(3, angle_min=1.6, angle_max=2.5, pid_kd=0.25)
        self.assertTrue(response.stored, response.error)
        wanted = dict(self.expected[3], angle_min=config_store.to_float32(1.6), angle_max=2.5,
                      pid_kd=0.25)
        self.assertEqual(joint_values(response.settings), wanted)
        self.assertEqual(joint_values(self.wait_stored(1).joints[3]), wanted)
        self.assertEqual(self.on_disk()[3], wanted)
        self.assertEqual(joint_values(proxy(3)), wanted, 'get_config serves the change')

        before = open(self.path, 'rb').read()
        for values, words in (({'pid_kp': 1.0, 'sign_motor': 0.5}, 'sign_motor = 0.5: a sign'),
                              ({'angle_max': 1.0}, 'angle_max = 1.0: below angle_min = 1.6'),
                              ({'voltage_max': 1e20}, 'outside its bound [-7.2, 7.2] V'),
                              ({'pid_kq': 1.0}, "unknown setting 'pid_kq'")):
            response = set_config(3, **values)
            self.assertFalse(response.stored)
            self.assertIn('joint 3', response.error)
            self.assertIn(words, response.error)
            self.assertEqual(joint_values(response.settings), wanted, 'unchanged, all or none')
        self.assertTrue(set_config(3, pid_kd=0.25).stored, 'a request equal to what is stored')
        self.assertEqual(open(self.path, 'rb').read(), before, 'nothing written')
        # Neither the refused nor the equal requests were published: the next change is 2.
        self.assertTrue(set_config(2, pid_kp=1.0).stored)
        changed = self.wait_stored(2)
        self.assertEqual(changed.joints[2].pid_kp, 1.0)
        self.assertEqual([m.revision for m in self.stored.messages()], [0, 1, 2])

        self.stop_node()
        self.stored.unregister()
        self.stored = StoredSettings()
        proxy = self.start_node(self.path)
        self.assertEqual(joint_values(proxy(3)), wanted, 'persisted')
        restarted = self.wait_stored(0)
        self.assertEqual(joint_values(restarted.joints[2]), dict(self.expected[2], pid_kp=1.0))

    def test_joint_topics_feed_the_same_path_and_get_config_is_unchanged(self):
        proxy = self.start_node(self.path)
        self.assertEqual(open(self.path).read(), open(FIXTURE).read(),
                         'the live file starts as a copy of the seed file')
        for joint in settings.JOINTS:
            self.assertEqual(joint_values(proxy(joint)), self.expected[joint])
        with self.assertRaises(rospy.ServiceException) as error:
            proxy(9)
        self.assertIn('0-6', str(error.exception))
        self.wait_stored(0)

        pub = rospy.Publisher(interface.joint_topic('R', 3, 'pid_kd'), Float32, queue_size=1,
                              latch=True)
        self.addCleanup(pub.unregister)  # a latched value must not reach the next test's node
        pub.publish(Float32(0.5))
        self.assertEqual(self.wait_stored(1).joints[3].pid_kd, 0.5)
        self.assertEqual(self.on_disk()[3]['pid_kd'], 0.5)
        self.assertEqual(proxy(3).pid_kd, 0.5)

        before = open(self.path, 'rb').read()
        bad = (('angle_min', float('nan'), 'joint 2 angle_min = nan: not a finite'),
               ('sign_motor', 0.5, 'joint 2 sign_motor = 0.5: a sign must be'),
               ('angle_min', 3.0, 'joint 2 angle_min = 3.0: above angle_max'),
               ('voltage_max', 1e20, 'joint 2 voltage_max = 1.0000000200408773e+20: outside '
                                     'its bound [-7.2, 7.2] V (the 7.2 V motor supply)'),
               ('pid_kp', 3.4e38, 'joint 2 pid_kp = 3.3999999521443642e+38: outside its bound '
                                  '[0, 10000] V/rad'))
        publishers = {name: rospy.Publisher(interface.joint_topic('R', 2, name), Float32,
                                            queue_size=10) for name, _, _ in bad}
        for publisher in publishers.values():
            self.addCleanup(publisher.unregister)
        self.assertTrue(wait_for(lambda: all(p.get_num_connections()
                                             for p in publishers.values())),
                        'config node never subscribed')
        for name, value, _ in bad:
            publishers[name].publish(Float32(value))
        for _, _, text in bad:
            self.wait_log('WARNING', text)
        self.assertEqual(joint_values(proxy(2)), self.expected[2], 'memory unchanged')
        after = open(self.path, 'rb').read()
        self.assertEqual(after, before, 'file unchanged')
        self.assertIn(b'# Test fixture', after, 'comments survive')
        # None of the refused values was published: the next change is revision 2.
        publishers['pid_kp'].publish(Float32(2.0))
        self.assertEqual(self.wait_stored(2).joints[2].pid_kp, 2.0)
        self.assertEqual([m.revision for m in self.stored.messages()], [0, 1, 2])


if __name__ == '__main__':
    rospy.init_node('test_config_node')
    rostest.rosrun('robopuppet', 'config_node', ConfigNodeTest)
