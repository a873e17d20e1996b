#!/usr/bin/python3
"""The GUI's joint tab against the real config node: Get shows what is stored, Set stores the
edits in one set_config request and shows what is stored, a refusal shows why and keeps the
edits, bad entries are refused with nothing sent.

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

from config_testing import SERVICE, StoredSettings, set_config
from gui_testing import application, wait_until
from robopuppet import settings
from robopuppet.config import config_store
from robopuppet.gui import joint_tab, settings_form
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
        cls.stored = StoredSettings()
        rospy.wait_for_service(SERVICE, 30.0)

    @classmethod
    def stop_config_node(cls):
        cls.stored.unregister()
        cls.config_node.send_signal(signal.SIGINT)
        try:
            cls.config_node.wait(10.0)
        except subprocess.TimeoutExpired:
            cls.config_node.kill()
            cls.config_node.wait()
        shutil.rmtree(cls.home)

    def tab(self):
        """Return a joint tab that has read the stored settings (Get, off the GUI thread)."""
        tab = JointTab(self.client, JOINT)
        tab.get()
        self.assertTrue(wait_until(lambda: not tab.busy(), 5.0))
        self.assertTrue(tab.message.text().startswith('read the stored'), tab.message.text())
        return tab

    def set_and_wait(self, tab):
        tab.set_button.click()
        self.assertTrue(wait_until(lambda: not tab.busy(), 10.0), tab.message.text())

    def revision(self):
        """Return the latest stored_settings revision received, once one was received."""
        self.assertTrue(wait_until(self.stored.messages, 10.0), 'no stored_settings')
        return self.stored.messages()[-1].revision

    def wait_revision(self, revision):
        msg = wait_until(lambda: self.stored.wait(revision, 0.0), 10.0)
        self.assertIsNotNone(msg, 'no stored_settings revision %d' % revision)
        return msg

    def test_get_shows_the_stored_settings(self):
        stored = self.client.get_config(JOINT)
        tab = self.tab()
        for name in settings.NAMES:
            self.assertEqual(tab.fields[name].text(), settings_form.field_text(stored[name]))

    def test_set_stores_the_edits_in_one_request_and_shows_what_is_stored(self):
        tab = self.tab()
        revision = self.revision()
        self.assertTrue(set_config(JOINT, pid_kd=0.125).stored, 'a change made elsewhere')
        self.wait_revision(revision + 1)
        tab.fields['pid_kp'].setText('0.750')
        tab.fields['angle_min'].setText('1.6')  # above the stored maximum, with a new maximum
        tab.fields['angle_max'].setText('2.5')
        self.set_and_wait(tab)
        self.assertTrue(tab.message.text().startswith('saved'), tab.message.text())
        self.assertEqual(tab.message.styleSheet(), joint_tab.OK_STYLE)
        stored = self.wait_revision(revision + 2).joints[JOINT]
        self.assertEqual((stored.pid_kp, stored.angle_max, stored.pid_kd), (0.75, 2.5, 0.125))
        self.assertEqual(stored.angle_min, config_store.to_float32(1.6))
        shown = {name: field.text() for name, field in tab.fields.items()}
        self.assertEqual(shown, {name: settings_form.field_text(getattr(stored, name))
                                 for name in settings.NAMES})
        self.assertEqual((shown['pid_kp'], shown['pid_kd']), ('0.75', '0.125'),
                         'the fields show what is stored, also a change made elsewhere')
        with open(self.ini_path) as ini:
            on_disk, _ = config_store.parse(ini.read())
        self.assertEqual(on_disk[JOINT]['pid_kp'], 0.75)
        self.assertEqual(on_disk[JOINT]['angle_max'], 2.5)
        fresh = self.tab()  # a new tab knows nothing but what Get reads
        self.assertEqual(fresh.fields['angle_min'].text(), '1.6')

    def test_a_refused_request_shows_why_and_keeps_the_edits(self):
        tab = self.tab()
        revision = self.revision()
        stored = self.client.get_config(JOINT)
        # The maximum lowered to the minimum elsewhere after Get: the tab still shows the old
        # maximum, so a new minimum up to it passes the tab's own checks.
        self.assertTrue(set_config(JOINT, angle_max=stored['angle_min']).stored)
        self.wait_revision(revision + 1)
        typed_min = settings_form.field_text(stored['angle_max'])
        tab.fields['angle_min'].setText(typed_min)
        tab.fields['pid_ki'].setText('0.5')
        self.set_and_wait(tab)
        self.assertIn('refused by config_R', tab.message.text())
        self.assertIn('angle_min = ', tab.message.text())
        self.assertIn(': above angle_max = %s' % config_store.format_value(stored['angle_min']),
                      tab.message.text())
        self.assertEqual(tab.message.styleSheet(), joint_tab.ERROR_STYLE)
        self.assertEqual(tab.fields['angle_min'].text(), typed_min)
        self.assertEqual(tab.fields['pid_ki'].text(), '0.5')
        self.assertEqual(tab.fields['angle_max'].text(),
                         settings_form.field_text(stored['angle_max']), 'fields as they were')
        # Nothing was stored: the next change is exactly one revision on.
        self.assertTrue(set_config(JOINT, angle_max=stored['angle_max']).stored)
        self.assertEqual(self.wait_revision(revision + 2).joints[JOINT].pid_ki,
                         stored['pid_ki'])
        self.assertEqual(self.revision(), revision + 2)

    def test_invalid_entries_are_refused_and_nothing_is_sent(self):
        revision = self.revision()
        before = self.client.get_config(JOINT)
        for name, text, words in (('pid_ki', 'twelve', 'not a number'),
                                  ('sign_motor', '0', 'sign'),
                                  ('voltage_min', '9', 'outside its bound'),
                                  ('angle_max', '-3', 'above angle_max = -3')):
            tab = self.tab()
            tab.fields[name].setText(text)
            tab.set_button.click()
            self.assertFalse(tab.busy(), 'refused on the GUI thread, no call made')
            self.assertIn('refused, nothing sent', tab.message.text())
            self.assertIn(words, tab.message.text())
            self.assertTrue(tab.message.isVisibleTo(tab))
        self.assertEqual(self.client.get_config(JOINT), before)
        # Nothing was stored: the next change is exactly one revision on.
        self.assertTrue(set_config(JOINT, pid_kd=before['pid_kd'] + 0.5).stored)
        self.wait_revision(revision + 1)
        self.assertEqual(self.revision(), revision + 1)


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'gui_config', GuiConfigTest)
