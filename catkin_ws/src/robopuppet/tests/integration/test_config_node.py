#!/usr/bin/python3
"""rostest: the real config node serves get_config, persists changes, refuses implausible ones,
survives a restart."""
import os
import shutil
import tempfile
import time
import unittest

import roslaunch
import rospy
import rostest
from rosgraph_msgs.msg import Log
from std_msgs.msg import Float32

from config_testing import FIXTURE, ConfigNodeRunner
from robopuppet.config import config_store



class ConfigNodeTest(ConfigNodeRunner, unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='robopuppet-config-')
        self.path = os.path.join(self.dir, 'arm_R.ini')
        self.launch = roslaunch.scriptapi.ROSLaunch()
        self.launch.start()
        self.process = None
        self.expected, _ = config_store.parse(open(FIXTURE).read())

    def tearDown(self):
        if self.process is not None:
            self.process.stop()
        self.launch.stop()
        shutil.rmtree(self.dir)

    def get(self, proxy, joint):
        response = proxy(joint)
        return {name: getattr(response, name) for name in config_store.settings.NAMES}

    def publish_and_wait(self, topic, value, proxy, joint, name, expect):
        pub = rospy.Publisher(topic, Float32, queue_size=1, latch=True)
        pub.publish(Float32(value))
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            if self.get(proxy, joint)[name] == expect:
                return
            time.sleep(0.05)
        self.fail('%s never became %r' % (name, expect))

    def test_serves_persists_and_refuses(self):
        proxy = self.start_node(self.path)
        self.assertEqual(open(self.path).read(), open(FIXTURE).read(),
                         'the live file starts as a copy of the seed file')
        for joint in range(7):
            self.assertEqual(self.get(proxy, joint), self.expected[joint])

        with self.assertRaises(rospy.ServiceException) as error:
            proxy(9)
        self.assertIn('0-6', str(error.exception))
        self.assertEqual(self.get(proxy, 3), self.expected[3], 'node keeps serving after joint 9')

        self.publish_and_wait('/puppet/arm_R/joint_3/pid_kd', 0.25, proxy, 3, 'pid_kd', 0.25)
        self.assertIn('pid_kd = 0.25', open(self.path).read())

        before = open(self.path).read()
        bad = (('angle_min', float('nan'), 'joint 2 angle_min = nan: not a finite'),
               ('sign_motor', 0.5, 'joint 2 sign_motor = 0.5: a sign must be'),
               ('angle_min', 3.0, 'joint 2 angle_min = 3.0: above angle_max'),
               # Plausibility bounds (issue 14 item 10): these reached the puppet before.
               ('voltage_max', 1e20, 'joint 2 voltage_max = 1.0000000200408773e+20: outside '
                                     'its bound [-7.2, 7.2] V (the 7.2 V motor supply)'),
               ('pid_kp', 3.4e38, 'joint 2 pid_kp = 3.3999999521443642e+38: outside its bound '
                                  '[0, 10000] V/rad'))
        warnings = []
        rospy.Subscriber('/rosout', Log, lambda m: warnings.append(m.msg) if m.level == Log.WARN
                         else None)
        publishers = {name: rospy.Publisher('/puppet/arm_R/joint_2/' + name, Float32,
                                            queue_size=10) for name, _, _ in bad}
        deadline = time.monotonic() + 10
        while not all(p.get_num_connections() for p in publishers.values()):
            self.assertLess(time.monotonic(), deadline, 'config node never subscribed')
            time.sleep(0.05)
        for name, value, _ in bad:
            publishers[name].publish(Float32(value))
            time.sleep(0.1)
        for _, _, text in bad:
            deadline = time.monotonic() + 10
            while not any(text in w for w in warnings):
                self.assertLess(time.monotonic(), deadline, 'no warning %r in %r' % (text, warnings))
                time.sleep(0.05)
        self.assertEqual(self.get(proxy, 2), self.expected[2], 'memory unchanged')
        after = open(self.path).read()
        self.assertEqual(after, before, 'file unchanged')
        self.assertIn('# Test fixture', after, 'comments survive')

        self.stop_node()
        proxy = self.start_node(self.path)
        self.assertEqual(self.get(proxy, 3)['pid_kd'], 0.25)
        self.assertEqual(self.get(proxy, 6)['pid_kp'], self.expected[6]['pid_kp'])


if __name__ == '__main__':
    rospy.init_node('test_config_node')
    rostest.rosrun('robopuppet', 'config_node', ConfigNodeTest)
