#!/usr/bin/python3
"""The GUI's joint tab against the real config node: Set persists, Get reads back, bad entries
are refused with nothing published.

The test starts config_R itself with ROS_HOME and ~file_name in a fresh temporary directory and
removes it at the end, so every run starts from the shipped settings and leaves nothing behind
(also under a plain `rostest robopuppet gui_config.test`).
"""
import os
import shutil
import signal
import subprocess
import tempfile
import unittest

import rospkg
import rospy
import rostest
from std_msgs.msg import Float32

from gui_testing import application, wait_for_subscribers, wait_until
from robopuppet import settings
from robopuppet.config import config_store
from robopuppet.gui import settings_form
from robopuppet.gui.joint_tab import JointTab
from robopuppet.gui.puppet_client import PuppetClient
from robopuppet.gui.state import ArmState

JOINT = 2


class GuiConfigTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('gui_config_test')
        application()
        cls.home = tempfile.mkdtemp(prefix='gui_config_test_')
        cls.ini_path = os.path.join(cls.home, 'arm_R.ini')
        seed = os.path.join(rospkg.RosPack().get_path('robopuppet'), 'config', 'arm_R.ini')
        cls.config_node = subprocess.Popen(
            ['rosrun', 'robopuppet', 'config', '__name:=config_R', '_arm_side:=R',
             '_file_name:=' + cls.ini_path, '_seed_file:=' + seed],
            env=dict(os.environ, ROS_HOME=cls.home, ROS_LOG_DIR=os.path.join(cls.home, 'log')))
        cls.addClassCleanup(cls.stop_config_node)
        cls.client = PuppetClient('R', ArmState())
        rospy.wait_for_service('/puppet/arm_R/get_config', 30.0)
        cls.heard = []
        cls.subs = [rospy.Subscriber('/puppet/arm_R/joint_%d/%s' % (JOINT, name), Float32,
                                     lambda msg, n=name: cls.heard.append((n, msg.data)))
                    for name in settings.NAMES]
        pubs = [cls.client._setting_pubs[JOINT, name] for name in settings.NAMES]
        assert wait_for_subscribers(pubs, 20.0), 'config node and test did not subscribe'
        wait_until(lambda: all(s.get_num_connections() for s in cls.subs), 10.0)

    @classmethod
    def stop_config_node(cls):
        cls.config_node.send_signal(signal.SIGINT)
        try:
            cls.config_node.wait(10.0)
        except subprocess.TimeoutExpired:
            cls.config_node.kill()
            cls.config_node.wait()
        shutil.rmtree(cls.home)

    def setUp(self):
        del self.heard[:]

    def tab(self):
        """Return a joint tab that has read the stored settings (Get, off the GUI thread)."""
        tab = JointTab(self.client, JOINT)
        tab.get()
        self.assertTrue(wait_until(lambda: not tab.busy(), 5.0))
        self.assertTrue(tab.message.text().startswith('read the stored'), tab.message.text())
        return tab

    def test_get_shows_the_stored_settings(self):
        stored = self.client.get_config(JOINT)
        tab = self.tab()
        for name in settings.NAMES:
            self.assertEqual(tab.fields[name].text(), settings_form.field_text(stored[name]))

    def test_set_publishes_and_a_later_get_shows_it_persisted(self):
        tab = self.tab()
        tab.fields['pid_kp'].setText('0.75')
        tab.fields['angle_min'].setText('1.6')  # above the stored maximum: max must go first
        tab.fields['angle_max'].setText('2.5')
        tab.set_button.click()
        self.assertTrue(wait_until(lambda: not tab.busy(), 10.0))
        self.assertTrue(tab.message.text().startswith('saved'), tab.message.text())
        self.assertTrue(wait_until(lambda: len(self.heard) >= 3, 5.0))
        self.assertEqual(sorted(self.heard), [('angle_max', 2.5), ('angle_min', 1.600000023841858),
                                              ('pid_kp', 0.75)])
        fresh = self.tab()  # a new tab knows nothing but what Get reads
        self.assertEqual(fresh.fields['pid_kp'].text(), '0.75')
        self.assertEqual(fresh.fields['angle_min'].text(), '1.6')
        self.assertEqual(fresh.fields['angle_max'].text(), '2.5')
        with open(self.ini_path) as ini:
            on_disk, _ = config_store.parse(ini.read())
        self.assertEqual(on_disk[JOINT]['pid_kp'], 0.75)
        self.assertEqual(on_disk[JOINT]['angle_max'], 2.5)

    def test_invalid_entries_are_refused_and_nothing_is_published(self):
        before = self.client.get_config(JOINT)
        for name, text, words in (('pid_ki', 'twelve', 'not a number'),
                                  ('sign_motor', '0', 'sign'),
                                  ('voltage_min', '9', 'outside its bound'),
                                  ('angle_max', '-3', 'below angle_min')):
            tab = self.tab()
            tab.fields[name].setText(text)
            tab.set_button.click()
            self.assertIn('refused', tab.message.text())
            self.assertIn(words, tab.message.text())
            self.assertTrue(tab.message.isVisibleTo(tab))
        wait_until(lambda: self.heard, 1.5)
        self.assertEqual(self.heard, [])
        self.assertEqual(self.client.get_config(JOINT), before)


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'gui_config', GuiConfigTest)
