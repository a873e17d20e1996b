#!/usr/bin/python3
"""serial_L's host -> device side: 64-byte writes, idempotent reloads, safe holds, a replug
without config_X, and the comm_rate check. The test publishes active_settings as config_X does.
"""
import time
import unittest

import roslaunch
import rospy
import rostest
from roslaunch.core import Node
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32, String

from robopuppet import interface, settings
from serial_test_support import SIM, ActiveSettings, Watcher, index, seed_values, topic
from waiting import wait_for

RATE_HZ = 50.0
HALL_REVERSED = 1  # joint 1: absolute encoder, sign_angle -1 and home_angle -0.125 in the ini


class SerialHostTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('serial_host_test')
        cls.seed = seed_values(rospy.get_param('~seed_file'))
        cls.link = rospy.get_param('~link')
        cls.watch = Watcher()
        cls.ticks = []  # every <sim>/control message
        cls.subs = [rospy.Subscriber(topic(interface.SIM_CONTROL, SIM), JointState,
                                     cls.ticks.append, queue_size=1000)]
        cls.pub_opmode = rospy.Publisher(topic(interface.OPMODE), String, queue_size=10)
        cls.pub_setpoint = [rospy.Publisher(interface.joint_topic('L', j, 'setpoint'), Float32,
                                            queue_size=10) for j in settings.JOINTS]
        cls.stored = ActiveSettings()
        cls.stored.publish(cls.seed)
        cls.launch = roslaunch.scriptapi.ROSLaunch()
        cls.launch.start()
        cls.sim = cls.serial = None
        cls.start_sim()
        cls.start_serial()

    @classmethod
    def tearDownClass(cls):
        for process in (cls.serial, cls.sim):
            if process is not None:
                process.stop()
        cls.launch.stop()

    @classmethod
    def start_sim(cls):
        if cls.sim is not None:
            cls.sim.stop()
        with cls.watch.lock:
            cls.watch.device_config = None
        cls.sim = cls.launch.launch(Node(
            'robopuppet', 'puppet_sim', name='puppet_sim_L', namespace='/',
            args='_arm_side:=L _state_rate:=%s _usb_packet_size:=64 _port_link:=%s'
            % (RATE_HZ, cls.link)))

    @classmethod
    def start_serial(cls, comm_rate_hz=RATE_HZ):
        if cls.serial is not None:
            cls.serial.stop()
        with cls.watch.lock:
            cls.watch.diagnostics = {}
        cls.serial = cls.launch.launch(Node(
            'robopuppet', 'serial_interface', name='serial_L', namespace='/',
            args='_arm_side:=L _port_name:=%s _comm_rate:=%s' % (cls.link, comm_rate_hz)))

    def wait_loaded(self, since_s, seed=None, timeout_s=20.0):
        """Wait until the device holds the settings and joint states flow again."""
        seed = self.seed if seed is None else seed
        self.assertTrue(wait_for(lambda: self.watch.device_config == seed, timeout_s),
                        'device holds %s, ini has %s' % (self.watch.device_config, seed))
        self.assertTrue(wait_for(lambda: len(self.watch.states_since(since_s)) >= 10,
                                      10.0), 'no joint states after the load')

    def angle(self, joint, since_s):
        """Wait until a joint's angle is steady (the device rate-limits the change a load
        makes); return its mean over the newest 10 sets since since_s."""
        def steady():
            states = self.watch.states_since(since_s)[-10:]
            angles = [s.position[joint] for s in states]
            return len(angles) == 10 and max(angles) - min(angles) < 0.002
        self.assertTrue(wait_for(steady, 10.0), 'joint %d never steady' % joint)
        states = self.watch.states_since(since_s)[-10:]
        return sum(s.position[joint] for s in states) / len(states)

    def restart_serial_and_angle(self, seed):
        """Restart serial_L (a second full load into the same device); return the angle."""
        restarted = time.monotonic()
        self.start_serial()
        self.assertTrue(wait_for(
            lambda: self.watch.diagnostics.get('settings loaded') == 'True', 20.0))
        self.wait_loaded(restarted, seed)
        return self.angle(HALL_REVERSED, restarted)

    def test_1_with_64_byte_usb_packets_all_84_settings_arrive(self):
        self.wait_loaded(0.0)
        self.assertEqual(len(self.seed), 84)

    def test_2_two_full_loads_give_the_same_angle_for_a_reversed_joint(self):
        self.wait_loaded(0.0)
        first = self.angle(HALL_REVERSED, 0.0)
        self.assertAlmostEqual(first, self.restart_serial_and_angle(self.seed), delta=0.01)

    def test_3_a_sign_change_alone_gives_what_a_full_load_gives(self):
        self.wait_loaded(0.0)
        seed = list(self.seed)
        seed[index(HALL_REVERSED, 'sign_angle')] = 1.0
        self.stored.publish(seed)
        self.wait_loaded(time.monotonic(), seed)
        after_change = self.angle(HALL_REVERSED, time.monotonic())  # sets made after the change
        self.assertAlmostEqual(after_change, self.restart_serial_and_angle(seed), delta=0.01)
        self.stored.publish(self.seed)  # back to the ini's values for the tests that follow
        self.assertTrue(wait_for(lambda: self.watch.device_config == self.seed, 10.0))

    def hold_ticks(self, count=50):
        """Return `count` control ticks in hold, from the device's going to hold on."""
        self.assertTrue(wait_for(lambda: self.watch.device_opmode == interface.HOLD, 5.0))
        start = len(self.ticks)
        self.assertTrue(wait_for(lambda: len(self.ticks) >= start + count, 10.0),
                        'no control ticks on %s/control' % SIM)
        return list(self.ticks[start:])

    def go_limp(self):
        self.pub_opmode.publish(String(interface.LIMP))
        self.assertTrue(wait_for(lambda: self.watch.device_opmode == interface.LIMP, 5.0))
        limp = time.monotonic()  # a few sets since: the angles where the limp arm is now
        self.assertTrue(wait_for(lambda: len(self.watch.states_since(limp)) >= 5, 5.0))

    def assert_no_zero_setpoint_away_from_zero(self, ticks):
        for tick in ticks:
            for joint, (setpoint, angle) in enumerate(zip(tick.position, tick.velocity)):
                if abs(angle) > 0.05:
                    self.assertGreater(abs(setpoint), 1e-3, 'joint %d at %.3f rad held with '
                                       'setpoint 0 (tick %s)' % (joint, angle, tick))

    def test_4_a_raw_hold_holds_where_the_puppet_is(self):
        self.wait_loaded(0.0)
        for _ in range(2):  # the second after a limp: the bookkeeping starts again
            self.go_limp()
            self.pub_opmode.publish(String(interface.HOLD))
            ticks = self.hold_ticks()
            away = [j for j in settings.JOINTS if abs(ticks[0].velocity[j]) > 0.05]
            self.assertGreaterEqual(len(away), 4, 'the rest pose should be away from 0')
            self.assert_no_zero_setpoint_away_from_zero(ticks)
        # Setpoints from arm_X win, whichever topic arrives first.
        self.go_limp()
        wanted = [round(a, 2) for a in self.watch.latest_state().position]
        self.pub_opmode.publish(String(interface.HOLD))
        for joint, value in enumerate(wanted):
            self.pub_setpoint[joint].publish(Float32(value + 0.02))
        self.assertTrue(wait_for(lambda: self.ticks and all(
            abs(s - (w + 0.02)) < 1e-4 for s, w in zip(self.ticks[-1].position, wanted)), 5.0))
        self.assert_no_zero_setpoint_away_from_zero(self.hold_ticks(25))
        self.go_limp()

    def test_5_a_replug_while_config_x_is_gone_loads_the_newest_active_settings(self):
        self.wait_loaded(0.0)
        self.stored.stop()  # config_X exits (or hangs: serial_L asks it nothing)
        try:
            self.assertTrue(wait_for(lambda: (
                self.watch.diagnostics.get('active settings publishers'),
                self.watch.diagnostics.get('level')) == ('0', 1), 10.0), self.watch.diagnostics)
            self.assertIn('nothing publishes', self.watch.diagnostics['message'])
            replugged = time.monotonic()
            self.start_sim()  # a fresh device, on firmware defaults
            self.wait_loaded(replugged, timeout_s=10.0)
            rospy.loginfo('settings loaded %.2f s after the replug, config_X gone',
                          time.monotonic() - replugged)
            # Loaded, but setting changes cannot come: a warning, not OK.
            self.assertTrue(wait_for(lambda: 'nothing publishes' in self.watch.diagnostics.get(
                'message', ''), 5.0), self.watch.diagnostics)
        finally:
            type(self).stored = ActiveSettings()
            self.stored.publish(self.seed)
        self.assertTrue(wait_for(lambda: self.watch.diagnostics.get('level') == 0, 10.0),
                        self.watch.diagnostics)

    def test_6_a_comm_rate_that_differs_from_the_measured_rate_is_reported(self):
        self.wait_loaded(0.0)
        self.start_serial(comm_rate_hz=10.0)  # the device sends 50 Hz
        self.assertTrue(wait_for(
            lambda: 'comm_rate' in self.watch.diagnostics.get('message', ''), 20.0),
            self.watch.diagnostics)
        self.assertEqual(self.watch.diagnostics['level'], 1)
        self.assertTrue(wait_for(lambda: self.watch.warnings_with('comm_rate is 10.0 Hz'),
                                      5.0))
        self.start_serial()


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'serial_host', SerialHostTest)
