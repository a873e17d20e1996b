"""What the feel-mode tests share (imported by test_feel_sim.py and test_feel_faults.py): the
simulated device's opmode, settings, PID voltages and the hand's torque, and the operator's way
from a calibrated puppet into feel mode with Baxter's right arm following."""
import threading
import time

import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, String

from robopuppet import interface, settings
from teleop_harness import max_error
from waiting import wait_for

SILENT = 'no joint states from the puppet'   # arm_R's fault when the puppet falls silent


class Device:
    """What the simulated puppet's device does (interface.sim_ns topics).

    Attributes: opmode (the device's own, 'limp' or 'hold': serial_X puts feel on the wire as
    hold), opmodes [(monotonic time, opmode)], and the operator-facing opmode_log of
    <ns>/opmode [(time, mode)] that the nodes publish to each other.
    """

    def __init__(self, side):
        self._lock = threading.Lock()
        self.opmode, self.opmodes, self.opmode_log = None, [], []
        self.config = None   # {setting name: [7 values]} the device holds
        self._torques, self._voltages, self._errors = [], [], []
        sim, ns = interface.sim_ns(side), interface.puppet_ns(side)
        rospy.Subscriber('%s/%s' % (sim, interface.SIM_DEVICE_OPMODE), String, self._on_opmode,
                         queue_size=10)
        rospy.Subscriber('%s/%s' % (sim, interface.SIM_HAND_TORQUE), JointState, self._on_torque,
                         queue_size=100)
        rospy.Subscriber('%s/%s' % (sim, interface.SIM_CONTROL), JointState, self._on_control,
                         queue_size=500)
        rospy.Subscriber('%s/%s' % (sim, interface.SIM_DEVICE_CONFIG), Float32MultiArray,
                         self._on_config, queue_size=10)
        rospy.Subscriber('%s/%s' % (ns, interface.OPMODE), String, self._on_told, queue_size=10)

    def _on_config(self, msg):
        count = len(settings.NAMES)
        rows = [msg.data[j * count:(j + 1) * count] for j in settings.JOINTS]
        self.config = {name: [row[i] for row in rows] for i, name in enumerate(settings.NAMES)}

    def _on_opmode(self, msg):
        with self._lock:
            self.opmode = msg.data
            self.opmodes.append((time.monotonic(), msg.data))

    def _on_told(self, msg):
        with self._lock:
            self.opmode_log.append((time.monotonic(), msg.data))

    def _on_torque(self, msg):
        with self._lock:
            self._torques.append(list(msg.effort))

    def _on_control(self, msg):   # position: setpoint, velocity: angle, effort: voltage
        with self._lock:
            self._voltages.append(list(msg.effort))
            self._errors.append([s - a for s, a in zip(msg.position, msg.velocity)])

    def mark(self):
        """Return a mark for torques_since / voltages_since."""
        with self._lock:
            return len(self._torques), len(self._voltages)

    def torques_since(self, mark):
        """Return the hand's torques (N m, 7 per row) published since mark."""
        with self._lock:
            return list(self._torques[mark[0]:])

    def voltages_since(self, mark):
        """Return the device's PID voltages (V, 7 per control tick in hold) since mark."""
        with self._lock:
            return list(self._voltages[mark[1]:])

    def errors_since(self, mark):
        """Return the device's setpoint - angle (rad, 7 per control tick in hold) since mark."""
        with self._lock:
            return list(self._errors[mark[1]:])


def follow_right(puppet, baxter):
    """Press button 3 until Baxter's right arm follows the puppet, and wait until it is on it."""
    wait_for(lambda: puppet.state() in (interface.READY, interface.FOLLOWING), 15,
             'ready to follow (now %s)' % puppet.state())
    if not puppet.teleop.follow_right:
        puppet.press(interface.BUTTON_RIGHT)
    wait_for(lambda: puppet.teleop.follow_right and puppet.state() == interface.FOLLOWING, 10,
             'following right (now %s, %r)' % (puppet.state(), puppet.teleop.detail))
    wait_for(lambda: max_error(baxter.arm('right'), puppet.angles) < 0.01, 30,
             'right arm on the puppet pose')


def fell_silent(puppet, since):
    """Return arm_R's fault detail if the puppet fell silent after monotonic time `since`."""
    for msg in puppet.reports_since(since):
        if msg.state == interface.FAULT and SILENT in msg.detail:
            return msg.detail
    return None


def into_feel(puppet, baxter, device, attempts=3):
    """Follow with Baxter's right arm and enter feel (follow_right, enter_feel).

    A simulated puppet starved of CPU on a loaded machine may fall silent for arm_R's state
    timeout (0.4 s at 10 Hz) on the way; arm_R then faults and the puppet goes limp, as it
    must. Then the operator starts again, up to `attempts` times in all; any other failure
    fails at once.
    """
    for attempt in range(attempts):
        begun = time.monotonic()
        try:
            follow_right(puppet, baxter)
            enter_feel(puppet, device)
            return
        except AssertionError:
            why = fell_silent(puppet, begun)
            if why is None or attempt == attempts - 1:
                raise
            rospy.logwarn('the puppet fell silent on the way into feel (%s); again', why)


def enter_feel(puppet, device):
    """Cycle button 1 from limp through hold into feel; wait until the device holds with feel
    mode's default voltage limits."""
    wait_for(lambda: puppet.teleop.opmode == interface.LIMP, 5,
             'opmode limp (now %s)' % puppet.teleop.opmode)
    puppet.press(interface.BUTTON_OPMODE)
    wait_for(lambda: puppet.teleop.opmode == interface.HOLD, 5, 'opmode hold')
    puppet.press(interface.BUTTON_OPMODE)
    wait_for(lambda: puppet.teleop.opmode == interface.FEEL, 5,
             'opmode feel (now %s)' % puppet.teleop.opmode)
    wait_for(lambda: device.opmode == interface.HOLD, 5,
             'the device holding in feel (now %s)' % device.opmode)
    limit = settings.FEEL_DEFAULTS['voltage_limit']
    wait_for(lambda: device.config is not None and max(device.config['voltage_max']) <= limit
             and min(device.config['voltage_min']) >= -limit, 5,
             "feel mode's voltage limits in the device")
