#!/usr/bin/python3
"""rostest: the real config node stores set_config requests all or none, publishes what it stores
on stored_settings, still takes the 2020 joint_J/<setting> topics, serves get_config as before,
refuses implausible values and survives a restart; it publishes active_settings, with feel
mode's gains from the file's [feel] section while the opmode is feel."""
import os
import shutil
import tempfile
import unittest

import roslaunch
import rospy
import rostest
from std_msgs.msg import Float32, String

from config_testing import (ACTIVE, FIXTURE, ConfigNodeRunner, StoredSettings, joint_values,
                            set_config)
from robopuppet import interface, settings
from robopuppet.config import config_store
from waiting import wait_for


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
                                             for p in publishers.values()), 10.0),
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

    def test_opmode_feel_makes_the_active_settings_gentle_and_never_reaches_the_file(self):
        active = StoredSettings(ACTIVE)
        self.addCleanup(active.unregister)
        opmode = rospy.Publisher(interface.puppet_ns('R') + '/' + interface.OPMODE, String,
                                 queue_size=10)
        self.addCleanup(opmode.unregister)
        self.start_node(self.path)
        first = active.wait(0)
        self.assertEqual((first.profile, [joint_values(j) for j in first.joints]),
                         ('', [self.expected[j] for j in settings.JOINTS]), 'latched at start')
        self.assertTrue(set_config(4, pid_ki=3.0, pid_kd=1.0, voltage_min=-5.0,
                                   voltage_max=1.0).stored)
        stored = {j: joint_values(v) for j, v in enumerate(self.wait_stored(1).joints)}
        self.assertTrue(wait_for(lambda: opmode.get_num_connections(), 10.0),
                        'no opmode subscriber')

        def newest():
            return wait_for(lambda: active.messages()[-1], 0.1)

        def gentle(values):  # the fixture's [feel]: gain_scale 0.5, voltage_limit 3 V
            return dict(values, pid_kp=values['pid_kp'] * 0.5, pid_ki=0.0,
                        pid_kd=values['pid_kd'] * 0.5, voltage_min=max(values['voltage_min'],
                                                                       -3.0),
                        voltage_max=min(values['voltage_max'], 3.0))
        opmode.publish(String(interface.FEEL))
        self.assertTrue(wait_for(lambda: newest().profile == 'feel', 10.0), 'no feel profile')
        feel = newest()
        self.assertEqual(feel.revision, 1)
        self.assertEqual([joint_values(j) for j in feel.joints],
                         [gentle(stored[j]) for j in settings.JOINTS])
        self.assertEqual((feel.joints[4].pid_ki, feel.joints[4].pid_kd, feel.joints[4].voltage_min,
                          feel.joints[4].voltage_max), (0.0, 0.5, -3.0, 1.0))
        count = len(active.messages())
        opmode.publish(String(interface.FEEL))  # a repeat changes nothing
        # A change stored in feel mode: the file gets the stored value, active its gentle one.
        self.assertTrue(set_config(4, pid_kp=4.0).stored)
        stored[4]['pid_kp'] = 4.0
        self.assertEqual(joint_values(self.wait_stored(2).joints[4]), stored[4])
        again = active.wait(2)
        self.assertEqual((again.profile, joint_values(again.joints[4])),
                         ('feel', gentle(stored[4])))
        self.assertEqual(len(active.messages()), count + 1, 'the repeated feel published nothing')
        self.assertEqual(self.on_disk(), stored, 'no feel gain in the joint sections')
        with open(self.path) as ini:
            self.assertEqual(config_store.parse_feel(ini.read()),
                             ({'gain_scale': 0.5, 'voltage_limit': 3.0}, []))
        for mode in (interface.HOLD, interface.FEEL, interface.LIMP):
            opmode.publish(String(mode))
            want = 'feel' if mode == interface.FEEL else ''
            self.assertTrue(wait_for(lambda: newest().profile == want, 10.0), mode)
            self.assertEqual([joint_values(j) for j in newest().joints], [
                gentle(stored[j]) if want else stored[j] for j in settings.JOINTS], mode)
        opmode.publish(String('stiff'))
        self.wait_log('WARNING', "opmode must be one of limp/hold/feel, got 'stiff'")
        self.assertEqual(newest().profile, '')


if __name__ == '__main__':
    rospy.init_node('test_config_node')
    rostest.rosrun('robopuppet', 'config_node', ConfigNodeTest)
