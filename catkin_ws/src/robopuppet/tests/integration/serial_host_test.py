#!/usr/bin/python3
"""serial_L's host -> device side: 64-byte writes, idempotent reloads, safe holds, a hung
config node, and the comm_rate check (issue 14 item 8; issue 16 items 1, 3, 5, 6)."""
import os
import signal
import threading
import time
import unittest

import roslaunch
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from roslaunch.core import Node
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32, String

from robopuppet import settings
from serial_test_support import NS, SIM, TempConfig, Watcher, seed_values, wait_for

RATE_HZ = 50.0
ID = settings.CONFIG_ID
HALL_REVERSED = 1  # joint 1: absolute encoder, sign_angle -1 and home_angle -0.125 in the ini


class SerialHostTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('serial_host_test')
        cls.seed_file = rospy.get_param('~seed_file')
        cls.seed = seed_values(cls.seed_file)
        cls.link = rospy.get_param('~link')
        cls.watch = Watcher()
        cls.lock = threading.Lock()
        cls.diagnostics = []  # (time, level, message) of every serial_L status
        cls.ticks = []  # every <sim>/control message
        cls.subs = [rospy.Subscriber('/diagnostics', DiagnosticArray, cls.on_diagnostics),
                    rospy.Subscriber(SIM + '/control', JointState, cls.on_control,
                                     queue_size=1000)]
        cls.pub_opmode = rospy.Publisher(NS + '/opmode', String, queue_size=10)
        cls.pub_setpoint = [rospy.Publisher('%s/joint_%d/setpoint' % (NS, j), Float32,
                                            queue_size=10) for j in settings.JOINTS]
        cls.launch = roslaunch.scriptapi.ROSLaunch()
        cls.launch.start()
        cls.config = TempConfig(cls.launch, cls.seed_file)
        cls.sim = cls.serial = None
        cls.start_sim()
        cls.start_serial()

    @classmethod
    def tearDownClass(cls):
        for process in (cls.serial, cls.sim):
            if process is not None:
                process.stop()
        cls.config.stop()
        cls.launch.stop()

    @classmethod
    def on_diagnostics(cls, msg):
        for status in msg.status:
            if status.name.startswith('/serial_L'):
                with cls.lock:
                    cls.diagnostics.append((time.monotonic(), status.level, status.message))

    @classmethod
    def on_control(cls, msg):
        with cls.lock:
            cls.ticks.append(msg)

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

    def wait_loaded(self, since_s, seed=None):
        """Wait until the device holds the settings and joint states flow again."""
        seed = self.seed if seed is None else seed
        self.assertIsNotNone(wait_for(lambda: self.watch.device_config == seed, 20.0),
                             'device holds %s, ini has %s' % (self.watch.device_config, seed))
        self.assertIsNotNone(wait_for(lambda: len(self.watch.states_since(since_s)) >= 10,
                                      10.0), 'no joint states after the load')

    def angle(self, joint, since_s):
        """Wait until a joint's angle is steady (the device rate-limits the change a load
        makes); return its mean over the newest 10 sets since since_s."""
        def steady():
            states = self.watch.states_since(since_s)[-10:]
            angles = [s.position[joint] for s in states]
            return len(angles) == 10 and max(angles) - min(angles) < 0.002
        self.assertIsNotNone(wait_for(steady, 10.0), 'joint %d never steady' % joint)
        states = self.watch.states_since(since_s)[-10:]
        return sum(s.position[joint] for s in states) / len(states)

    def warnings(self, text):
        with self.watch.lock:
            return [w for w in self.watch.warnings if text in w]

    def test_1_with_64_byte_usb_packets_all_84_settings_arrive(self):
        self.wait_loaded(0.0)
        self.assertEqual(len(self.seed), 84)

    def test_2_two_full_loads_give_the_same_angle_for_a_reversed_joint(self):
        self.wait_loaded(0.0)
        first = self.angle(HALL_REVERSED, 0.0)
        restarted = time.monotonic()
        self.start_serial()  # a new serial node loads the same settings into the same device
        self.assertIsNotNone(wait_for(
            lambda: self.watch.diagnostics.get('settings loaded') == 'True', 20.0))
        self.wait_loaded(restarted)
        again = self.angle(HALL_REVERSED, restarted)
        self.assertAlmostEqual(first, again, delta=0.01)

    def test_3_a_sign_change_alone_gives_what_a_full_load_gives(self):
        self.wait_loaded(0.0)
        sign = rospy.Publisher('%s/joint_%d/sign_angle' % (NS, HALL_REVERSED), Float32,
                               queue_size=1)
        self.assertIsNotNone(wait_for(lambda: sign.get_num_connections() >= 2, 5.0))
        seed = list(self.seed)
        seed[HALL_REVERSED * len(settings.NAMES) + ID['sign_angle']] = 1.0
        changed = time.monotonic()
        sign.publish(Float32(1.0))
        self.wait_loaded(changed, seed)
        time.sleep(0.5)
        after_change = self.angle(HALL_REVERSED, changed)
        restarted = time.monotonic()
        self.start_serial()
        self.assertIsNotNone(wait_for(
            lambda: self.watch.diagnostics.get('settings loaded') == 'True', 20.0))
        self.wait_loaded(restarted, seed)
        self.assertAlmostEqual(after_change, self.angle(HALL_REVERSED, restarted),
                               delta=0.01)
        sign.publish(Float32(-1.0))  # back to the ini's value for the tests that follow
        self.assertIsNotNone(wait_for(lambda: self.watch.device_config == self.seed, 10.0))

    def hold_ticks(self, duration_s=1.5):
        """Return the control ticks in hold over duration_s after the device went to hold."""
        self.assertIsNotNone(wait_for(lambda: self.watch.device_opmode == 'hold', 5.0))
        start = len(self.ticks)
        self.assertIsNotNone(wait_for(lambda: len(self.ticks) >= start + 10, 10.0),
                             'no control ticks on %s/control' % SIM)
        time.sleep(duration_s)
        with self.lock:
            return list(self.ticks[start:])

    def go_limp(self):
        self.pub_opmode.publish(String('limp'))
        self.assertIsNotNone(wait_for(lambda: self.watch.device_opmode == 'limp', 5.0))
        time.sleep(0.3)

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
            self.pub_opmode.publish(String('hold'))
            ticks = self.hold_ticks()
            away = [j for j in settings.JOINTS if abs(ticks[0].velocity[j]) > 0.05]
            self.assertGreaterEqual(len(away), 4, 'the rest pose should be away from 0')
            self.assert_no_zero_setpoint_away_from_zero(ticks)
        # Setpoints from arm_X win, whichever topic arrives first.
        self.go_limp()
        wanted = [round(a, 2) for a in self.watch.latest_state().position]
        self.pub_opmode.publish(String('hold'))
        for joint, value in enumerate(wanted):
            self.pub_setpoint[joint].publish(Float32(value + 0.02))
        self.assertIsNotNone(wait_for(lambda: self.ticks and all(
            abs(s - (w + 0.02)) < 1e-4 for s, w in zip(self.ticks[-1].position, wanted)), 5.0))
        self.assert_no_zero_setpoint_away_from_zero(self.hold_ticks(0.5))
        self.go_limp()

    def test_5_a_hung_config_node_stalls_nothing_and_a_replug_loads_when_it_answers(self):
        self.wait_loaded(0.0)
        pid = self.config.process.get_info()['pid']
        os.kill(pid, signal.SIGSTOP)
        try:
            frozen = time.monotonic()
            self.start_sim()  # a replug during the freeze
            self.assertIsNotNone(wait_for(
                lambda: 'unreachable' in self.watch.diagnostics.get('message', ''), 15.0),
                self.watch.diagnostics)
            time.sleep(4.0)
            with self.lock:
                during = [d for d in self.diagnostics if d[0] >= frozen]
            self.assertGreaterEqual(len(during), 5, 'diagnostics stalled: %s' % during)
            self.assertTrue(all(d[1] >= 1 for d in during[-3:]), during)
            self.assertEqual(self.watch.diagnostics['settings loaded'], 'False')
            # No settings, no angles: a raw hold is refused, the device stays limp.
            self.pub_opmode.publish(String('hold'))
            self.assertIsNotNone(wait_for(lambda: self.warnings('hold refused'), 5.0))
            self.assertEqual(self.watch.device_opmode, 'limp')
        finally:
            os.kill(pid, signal.SIGCONT)
        resumed = time.monotonic()
        self.wait_loaded(resumed)
        took = time.monotonic() - resumed
        rospy.loginfo('settings loaded %.2f s after the config node resumed', took)
        self.assertLess(took, 8.0)
        self.assertIsNotNone(wait_for(
            lambda: self.watch.diagnostics.get('config node') == 'reachable', 5.0))

    def test_6_a_comm_rate_that_differs_from_the_measured_rate_is_reported(self):
        self.wait_loaded(0.0)
        self.start_serial(comm_rate_hz=10.0)  # the device sends 50 Hz
        self.assertIsNotNone(wait_for(
            lambda: 'comm_rate' in self.watch.diagnostics.get('message', ''), 20.0),
            self.watch.diagnostics)
        self.assertEqual(self.watch.diagnostics['level'], 1)
        self.assertIsNotNone(wait_for(lambda: self.warnings('comm_rate is 10.0 Hz'), 5.0))
        self.start_serial()


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'serial_host', SerialHostTest)
