#!/usr/bin/python3
"""The GUI against the simulated arm: a slider moves the simulated hand and the main tab shows
the puppet following; the buttons and the opmode control reach the puppet."""
import unittest

import rospy
import rostest
from sensor_msgs.msg import JointState
from std_msgs.msg import String

from gui_testing import application, wait_until
from robopuppet.gui.puppet_client import PuppetClient, SimPuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.window import Window

JOINT = 1  # an absolute-encoder joint: Working from the start


class GuiSimTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('gui_sim_test')
        application()
        cls.client = PuppetClient('R', ArmState())
        cls.window = Window(cls.client, debug_mode=False, sim=SimPuppetClient('R'))
        cls.panel = cls.window.sim_panel
        cls.hands = []
        cls.opmodes = []
        rospy.Subscriber('/puppet_sim/arm_R/hand', JointState, cls.hands.append)
        rospy.Subscriber('/puppet_sim/arm_R/device_opmode', String,
                         lambda msg: cls.opmodes.append(msg.data))

    def cell(self, row, column):
        self.window.frame()
        return self.window.main_tab.joint_table.item(row, column).text()

    def reported_angle(self):
        text = self.cell(JOINT, 1)
        return None if text == '—' else float(text)

    def test_a_slider_moves_the_simulated_hand_and_the_main_tab_shows_it(self):
        self.assertTrue(wait_until(lambda: self.cell(JOINT, 0) == 'Working', 30.0),
                        'joint %d never reported Working' % JOINT)
        start = self.reported_angle()
        target = -0.4 if start > 0 else 0.4
        self.panel.set_angle(JOINT, target)
        self.assertTrue(wait_until(lambda: self.hands, 5.0), 'no hand message')
        self.assertAlmostEqual(self.hands[-1].position[JOINT], target)
        self.assertEqual(self.hands[-1].name[JOINT], 'joint_%d' % JOINT)
        # sign_angle +1 and home_angle 0 in the shipped arm_R.ini: the angle follows the hand.
        self.assertTrue(wait_until(lambda: abs(self.reported_angle() - target) < 0.05, 20.0),
                        'joint %d reports %s, hand at %s' % (JOINT, self.reported_angle(), target))
        self.assertIn('s ago', self.window.main_tab.heartbeat_label.text())

    def test_buttons_end_piece_and_opmode_reach_the_puppet(self):
        panel, tab = self.panel, self.window.main_tab
        panel.user_buttons[2].pressed.emit()
        self.assertTrue(wait_until(lambda: self.client.state.snapshot().button == 3, 10.0))
        panel.user_buttons[2].released.emit()
        self.assertTrue(wait_until(lambda: self.client.state.snapshot().button == 0, 10.0))
        self.window.frame()
        self.assertIn('last pressed: 3', tab.button_label.text())
        panel.end_piece_button.setDown(True)
        panel.end_piece_button.pressed.emit()
        self.assertTrue(wait_until(lambda: self.client.state.snapshot().grippers[3] < 0.1, 10.0))
        panel.end_piece_button.setDown(False)
        panel.end_piece_button.released.emit()
        self.assertTrue(wait_until(lambda: self.client.state.snapshot().grippers[3] > 0.9, 10.0))
        tab.hold_radio.click()
        self.assertTrue(wait_until(lambda: self.opmodes and self.opmodes[-1] == 'hold', 10.0),
                        'device opmodes: %s' % self.opmodes)
        tab.limp_radio.click()
        self.assertTrue(wait_until(lambda: self.opmodes[-1] == 'limp', 10.0))


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'gui_sim', GuiSimTest)
