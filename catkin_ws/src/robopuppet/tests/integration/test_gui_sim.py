#!/usr/bin/python3
"""The GUI against the simulated arm: a slider moves the simulated hand and the main tab shows
the puppet following; the buttons and the opmode control reach the puppet, Hold keeps the
puppet where it is, Feel without Baxter ends limp at once (arm_R), and a joint tab's Set reaches
the device through config_R and serial_R."""
import time
import unittest

import rospy
import rostest
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, String

from gui_testing import application, wait_until
from robopuppet import interface, settings
from robopuppet.config import config_store
from robopuppet.gui.joint_tab import JointTab
from robopuppet.gui.puppet_client import PuppetClient, SimPuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.window import Window

JOINT = 1  # an absolute-encoder joint: Working from the start
TUNED_JOINT = 5  # the joint whose D gain the settings test changes
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
        cls.device_configs = []  # (arrival s, the 84 settings the simulated device holds)
        cls.sent_opmodes = []  # what anyone publishes on /puppet/arm_R/opmode
        rospy.Subscriber('%s/%s' % (interface.puppet_ns('R'), interface.OPMODE), String,
                         lambda msg: cls.sent_opmodes.append(msg.data))
        sim = interface.sim_ns('R')
        rospy.Subscriber('%s/%s' % (sim, interface.SIM_HAND), JointState, cls.hands.append)
        rospy.Subscriber('%s/%s' % (sim, interface.SIM_DEVICE_OPMODE), String,
                         lambda msg: cls.opmodes.append(msg.data))
        rospy.Subscriber('%s/%s' % (sim, interface.SIM_CONTROL), JointState,
                         lambda msg: cls.ticks.append((list(msg.position), list(msg.velocity))),
                         queue_size=500)
        rospy.Subscriber('%s/%s' % (sim, interface.SIM_DEVICE_CONFIG), Float32MultiArray,
                         lambda msg: cls.device_configs.append((time.monotonic(), msg.data)))

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
        self.assertTrue(wait_until(lambda: self.cell(JOINT, 0) == interface.WORKING, 30.0),
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
        self.assertTrue(wait_until(lambda: self.opmodes and self.opmodes[-1] == interface.HOLD,
                                   10.0),
                        'device opmodes: %s' % self.opmodes)
        self.assertTrue(wait_until(lambda: len(self.ticks) >= 25, 10.0), 'no control ticks')
        zero = [tick for tick in self.ticks
                if any(s == 0.0 and abs(a) > 0.1 for s, a in zip(*tick))]
        self.assertEqual(zero, [], 'hold drove a joint away from 0 rad toward 0 rad')
        for setpoints, _ in self.ticks:  # and it holds the puppet where it was
            self.assertLess(max(abs(s - a) for s, a in zip(setpoints, before)), 0.02,
                            'setpoints %s, puppet was at %s' % (setpoints, before))
        tab.limp_radio.click()
        self.assertTrue(wait_until(lambda: self.opmodes[-1] == interface.LIMP, 10.0))

    def test_feel_without_baxter_ends_limp_and_never_drives_toward_0_rad(self):
        """Feel from the radio publishes feel (the GUI sends the current angles first, as for
        hold); arm_R has no Baxter, so it ends feel at once (limp on opmode, docs/feel.md):
        the device may hold for a moment, only ever where the puppet is, and ends limp, and the
        radios show limp. The GUI's feel and arm_R's limp come from two publishers, so serial_R
        may get them in either order: with feel last, its feel watchdog (no setpoints for 0.5 s)
        makes the device limp all the same."""
        tab = self.window.main_tab
        self.window.sim.set_hand(AWAY)
        self.assertTrue(wait_until(self.angles_settled, 20.0), 'the puppet never settled')
        if self.client.state.snapshot().opmode != interface.LIMP:
            tab.limp_radio.click()
            self.assertTrue(wait_until(lambda: self.opmodes[-1] == interface.LIMP, 10.0))
        before, ticks_from, sent_from = self.angles(), len(self.ticks), len(self.sent_opmodes)
        tab.feel_radio.click()
        self.assertTrue(wait_until(lambda: self.sent_opmodes[sent_from:] == [
            interface.FEEL, interface.LIMP], 10.0),
            'opmode topic after feel: %s' % self.sent_opmodes[sent_from:])
        self.assertTrue(wait_until(lambda: self.client.state.snapshot().opmode
                                   == interface.LIMP, 5.0), 'the GUI never heard of limp')
        # Limp within the feel watchdog's 0.5 s (+ margin for a busy machine), and it stays so.
        self.assertTrue(wait_until(lambda: self.opmodes[-1] == interface.LIMP, 3.0),
                        'device opmodes: %s' % self.opmodes[-5:])
        time.sleep(0.5)  # a hold frame still on its way would show by now
        self.assertEqual(self.opmodes[-1], interface.LIMP)
        for setpoints, _ in self.ticks[ticks_from:]:  # held where it was, if at all
            self.assertLess(max(abs(s - a) for s, a in zip(setpoints, before)), 0.02,
                            'setpoints %s, puppet was at %s' % (setpoints, before))
        self.window.frame()
        self.assertTrue(tab.limp_radio.isChecked() and not tab.feel_radio.isChecked())

    def device_kd(self):
        """Return the D gain of TUNED_JOINT that the simulated device holds, and since when."""
        if not self.device_configs:
            return None, None
        arrival_s, values = self.device_configs[-1]
        return values[TUNED_JOINT * len(settings.NAMES) + settings.CONFIG_ID['pid_kd']], arrival_s

    def test_a_set_in_a_joint_tab_reaches_the_device_as_soon_as_it_is_stored(self):
        """One path, no timers: Set -> set_config (config_R stores it and publishes
        stored_settings) -> serial_R sends what differs -> the device holds it."""
        tab = JointTab(self.client, TUNED_JOINT)
        tab.get()
        self.assertTrue(wait_until(lambda: not tab.busy(), 10.0), tab.message.text())
        self.assertTrue(wait_until(lambda: self.device_kd()[0] == tab.stored['pid_kd'], 20.0),
                        'the device never held the stored settings: %s' % (self.device_kd(),))
        new_kd = config_store.to_float32(tab.stored['pid_kd'] + 0.125)
        tab.fields['pid_kd'].setText(repr(new_kd))
        tab.set_button.click()
        self.assertTrue(wait_until(lambda: not tab.busy(), 10.0), tab.message.text())
        answered_s = time.monotonic()
        self.assertTrue(tab.message.text().startswith('saved'), tab.message.text())
        # The simulated device reports its settings at most every 0.1 s: held within 0.5 s of
        # the answer means no re-read timer (the old path took 0.2 s, or 2 s, to re-read).
        self.assertTrue(wait_until(lambda: self.device_kd()[0] == new_kd, 0.5),
                        'device D gain %s, stored %s' % (self.device_kd()[0], new_kd))
        rospy.loginfo('set_config answer to device: %.3f s',
                      self.device_kd()[1] - answered_s)


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'gui_sim', GuiSimTest)
