#!/usr/bin/python3
"""The GUI against the simulated arm: a slider moves the simulated hand and the main tab shows
the puppet following; the buttons and the opmode control reach the puppet, and Hold keeps the
puppet where it is."""
import time
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
AWAY = [0.3, -0.4, 0.3, 0.5, -0.3, 0.4, 0.3]  # a hand pose away from 0 rad on every joint


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
        cls.ticks = []  # (setpoints, reported angles) of each control tick in hold
        rospy.Subscriber('/puppet_sim/arm_R/hand', JointState, cls.hands.append)
        rospy.Subscriber('/puppet_sim/arm_R/device_opmode', String,
                         lambda msg: cls.opmodes.append(msg.data))
        rospy.Subscriber('/puppet_sim/arm_R/control', JointState,
                         lambda msg: cls.ticks.append((list(msg.position), list(msg.velocity))),
                         queue_size=500)

    def cell(self, row, column):
        self.window.frame()
        return self.window.main_tab.joint_table.item(row, column).text()

    def reported_angle(self):
        text = self.cell(JOINT, 1)
        return None if text == '—' else float(text)

    def angles(self):
        return [joint.angle_rad for joint in self.client.state.snapshot().joints]

    def angles_settled(self):
        """Return True once the GUI's angles of all joints changed less than 2 mrad in 0.3 s."""
        before = self.angles()
        time.sleep(0.3)
        return all(abs(a - b) < 0.002 for a, b in zip(self.angles(), before))

    def test_a_slider_moves_the_simulated_hand_and_the_main_tab_shows_it(self):
        self.assertTrue(wait_until(lambda: self.cell(JOINT, 0) == 'Working', 30.0),
                        'joint %d never reported Working' % JOINT)
        self.assertTrue(wait_until(lambda: self.reported_angle() is not None, 10.0),
                        'joint %d shows no angle' % JOINT)
        start = self.reported_angle()
        target = -0.4 if start > 0 else 0.4
        self.panel.set_angle(JOINT, target)
        self.assertTrue(wait_until(lambda: self.hands, 5.0), 'no hand message')
        self.assertAlmostEqual(self.hands[-1].position[JOINT], target)
        self.assertEqual(self.hands[-1].name[JOINT], 'joint_%d' % JOINT)
        # sign_angle +1 and home_angle 0 in the shipped arm_R.ini: the angle follows the hand.
        self.assertTrue(wait_until(lambda: abs(self.reported_angle() - target) < 0.05, 20.0),
                        'joint %d reports %s, hand at %s' % (JOINT, self.reported_angle(), target))
        self.assertTrue(wait_until(lambda: 's ago' in self.heartbeat_text(), 5.0),
                        self.heartbeat_text())  # the serial node counts heartbeats at ~1 Hz

    def heartbeat_text(self):
        self.window.frame()
        return self.window.main_tab.heartbeat_label.text()

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
        # Hold with the puppet away from 0 rad: the firmware keeps the setpoints it has (0 rad
        # after limp), so the GUI must send the current angles first.
        self.window.sim.set_hand(AWAY)
        self.assertTrue(wait_until(self.angles_settled, 20.0), 'the puppet never settled')
        before = self.angles()
        tab.hold_radio.click()
        self.assertTrue(wait_until(lambda: self.opmodes and self.opmodes[-1] == 'hold', 10.0),
                        'device opmodes: %s' % self.opmodes)
        self.assertTrue(wait_until(lambda: len(self.ticks) >= 25, 10.0), 'no control ticks')
        zero = [tick for tick in self.ticks
                if any(s == 0.0 and abs(a) > 0.1 for s, a in zip(*tick))]
        self.assertEqual(zero, [], 'hold drove a joint away from 0 rad toward 0 rad')
        for setpoints, _ in self.ticks:  # and it holds the puppet where it was
            self.assertLess(max(abs(s - a) for s, a in zip(setpoints, before)), 0.02,
                            'setpoints %s, puppet was at %s' % (setpoints, before))
        tab.limp_radio.click()
        self.assertTrue(wait_until(lambda: self.opmodes[-1] == 'limp', 10.0))


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'gui_sim', GuiSimTest)
