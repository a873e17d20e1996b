#!/usr/bin/python3
"""rostest: faults in feel mode leave the puppet limp (feel_faults.test: main_sim headless, its
default zones and obstacles).

Each fault is a process frozen with SIGSTOP (found by its pid through its own XML-RPC API) and
thawed with SIGCONT: the Baxter stand-in (robot absent: arm_R takes the puppet out of feel), the
robot host's arm controller arm_R (nobody streams setpoints: serial_R's feel watchdog sends limp
on its own) and the simulated puppet (silent: arm_R faults). After each the device stays limp
until the operator chooses feel again. Then feel from limp with the puppet far from Baxter: the
device holds on the feel gains from its first control tick (serial_R loads them before the hold).
"""
import contextlib
import os
import signal
import time
import unittest

import rospy
import rostest

from feel_harness import Device, into_feel
from hand_pose import HAND_POSE
from robopuppet import interface, settings
from teleop_harness import Baxter, PuppetArm, calibrate, max_error, node_pid
from waiting import wait_for

# serial_R's feel watchdog: ~feel_setpoint_timeout (0.5 s) and the frame on the wire; the margin
# is for a loaded machine.
WATCHDOG_LIMP_S = 1.5
ELBOW, AWAY_RAD = 3, 0.3   # the puppet's elbow this far from Baxter's: 6 V on the stored gains
FEEL_ENTRIES = 5


@contextlib.contextmanager
def frozen(node):
    """SIGSTOP a node for the block (SIGCONT after, whatever happens); yield the moment."""
    pid = node_pid(node)
    os.kill(pid, signal.SIGSTOP)
    try:
        yield time.monotonic()
    finally:
        os.kill(pid, signal.SIGCONT)


class FeelFaultsTest(unittest.TestCase):

    def assert_stays_limp(self, puppet, device, seconds):
        """The device and every node's opmode stay limp for `seconds`."""
        wait_for(lambda: puppet.teleop.opmode == interface.LIMP, 10,
                 'teleop opmode limp (now %s)' % puppet.teleop.opmode)
        since = time.monotonic()
        time.sleep(seconds)
        self.assertEqual(device.opmode, interface.LIMP)
        self.assertEqual([m for t, m in device.opmodes if t > since], [])
        self.assertEqual(puppet.teleop.opmode, interface.LIMP)

    def test_every_fault_in_feel_leaves_the_puppet_limp(self):
        puppet, baxter, device = PuppetArm('R'), Baxter(), Device('R')
        wait_for(lambda: puppet.state() == interface.CALIBRATING, 30, 'arm_R calibrating')
        puppet.end_piece(False)
        calibrate(puppet, HAND_POSE)
        wait_for(lambda: puppet.state() == interface.READY, 5, 'ready')

        # The robot goes absent: arm_R takes the puppet out of feel.
        into_feel(puppet, baxter, device)
        with frozen('/baxter_sim'):
            wait_for(lambda: device.opmode == interface.LIMP, 10,
                     'the device limp without the robot (teleop %s, %r)' % (
                         puppet.state(), puppet.teleop.detail))
            wait_for(lambda: puppet.state() in (interface.NO_ROBOT, interface.FAULT), 5,
                     'teleop_state saying the robot is gone (now %s)' % puppet.state())
        self.assert_stays_limp(puppet, device, 2.0)

        # The robot host's controller stops: serial_R's watchdog sends limp itself.
        into_feel(puppet, baxter, device)
        told = len(device.opmode_log)
        with frozen('/arm_R') as stopped_t:
            wait_for(lambda: device.opmode == interface.LIMP, 5,
                     'the device limp without arm_R')
            limp_t = [t for t, m in device.opmodes if m == interface.LIMP][-1]
            self.assertGreater(limp_t, stopped_t)
            rospy.loginfo('feel_faults: the device went limp %.2f s after arm_R stopped',
                          limp_t - stopped_t)
            self.assertLess(limp_t - stopped_t, WATCHDOG_LIMP_S)
            wait_for(lambda: interface.LIMP in [m for _, m in device.opmode_log[told:]], 5,
                     'limp published on %s' % interface.OPMODE)
        self.assert_stays_limp(puppet, device, 2.0)   # arm_R, thawed, follows the limp

        # The puppet goes silent: arm_R faults and sends limp, which the device obeys once it
        # runs again.
        into_feel(puppet, baxter, device)
        with frozen('/puppet_sim_R'):
            wait_for(lambda: puppet.state() == interface.FAULT, 5, 'fault on a silent puppet')
            wait_for(lambda: puppet.teleop.opmode == interface.LIMP, 5, 'teleop opmode limp')
        wait_for(lambda: device.opmode == interface.LIMP, 10, 'the device limp once it runs')
        self.assert_stays_limp(puppet, device, 2.0)

        # Feel from limp (the GUI's switch), the elbow 0.3 rad from Baxter's: the stored gains
        # (pid_kp 20 V/rad) would ask 6 V at once, feel's 1.5 V, within 2 V. Five times: a
        # control tick every 20 ms, and the gains' writes take about as long.
        wait_for(lambda: puppet.state() == interface.READY, 10,
                 'ready (now %s, %r)' % (puppet.state(), puppet.teleop.detail))
        away = list(baxter.arm('right'))
        away[ELBOW] += AWAY_RAD if away[ELBOW] < 0.5 else -AWAY_RAD
        puppet.hand(away)
        for _ in range(FEEL_ENTRIES):
            self.assert_feel_starts_on_its_gains(puppet, device, away)

    def assert_feel_starts_on_its_gains(self, puppet, device, away):
        """Set feel with the puppet at `away`: the device pulls toward Baxter, and no control
        tick from its first in hold is beyond feel's voltage limit; then limp again."""
        wait_for(lambda: max_error(puppet.angles, away) < 0.05, 10,
                 'the puppet away from Baxter (at %s, to %s)' % (puppet.angles, away))
        mark = device.mark()
        puppet.set_opmode(interface.FEEL)
        wait_for(lambda: device.opmode == interface.HOLD, 5, 'the device holding in feel')
        wait_for(lambda: len(device.voltages_since(mark)) >= 25, 5, 'half a second of ticks')
        errors, voltages = device.errors_since(mark), device.voltages_since(mark)
        self.assertGreater(max(abs(e[ELBOW]) for e in errors), AWAY_RAD - 0.1,
                           'no pull toward Baxter')
        most_v = max(abs(v) for tick in voltages for v in tick)
        rospy.loginfo('feel_faults: feel from limp, %d ticks, |PID voltage| at most %.2f V',
                      len(voltages), most_v)
        self.assertLessEqual(most_v, settings.FEEL_DEFAULTS['voltage_limit'] + 1e-4,
                             'a control tick beyond the feel voltage_limit (the first of %d: %s)'
                             % (len(voltages), voltages[:3]))
        self.assertEqual(puppet.teleop.opmode, interface.FEEL)
        puppet.set_opmode(interface.LIMP)
        wait_for(lambda: device.opmode == interface.LIMP, 5, 'the device limp again')


if __name__ == '__main__':
    rospy.init_node('test_feel_faults')
    rostest.rosrun('robopuppet', 'feel_faults', FeelFaultsTest)
