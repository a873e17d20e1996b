"""Operator's hand and observer for end-to-end tests of main_sim.launch (imported by the tests).

Plays the operator through the simulated puppet's operator topics (interface.sim_ns(side)) and
records what the puppet reports and what Baxter is told and does, with reception times. Every
wait is on a condition with a deadline, paced by what the puppet reports (its state sets), so
the same steps work at any comm_rate.
"""
import collections
import contextlib
import math
import threading
import time
import xmlrpc.client

import rosgraph
import rospy
from baxter_core_msgs.msg import EndEffectorState, JointCommand
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, String, UInt8

from robopuppet import baxter_description, interface, settings
from robopuppet_msgs.msg import TeleopState

from waiting import wait_for

RELEASED = [1.0 if g == interface.END_PIECE_GRIPPER else 0.0   # the end-piece button released
            for g in range(interface.NUM_GRIPPERS)]
PRESSED = [0.0] * interface.NUM_GRIPPERS
STILL_RAD = 1e-3   # a puppet whose angles change less than this over STILL_SETS sets is still
STILL_SETS = 3


def max_error(a, b):
    return max(abs(x - y) for x, y in zip(a, b))


class PuppetArm:
    """One simulated puppet arm: the operator's side of it and what it reports.

    Attributes (each newest first received): angles (rad), states_t (reception time of every
    joint_states), statuses, button (the user button the puppet reports), teleop (the newest
    TeleopState), teleop_log [(reception time, TeleopState)], diag {key: value} of arm_X's
    teleoperation status on /diagnostics, diag_status (that DiagnosticStatus).
    """

    def __init__(self, side):
        self.side = side
        sim, ns = interface.sim_ns(side), interface.puppet_ns(side)
        self._lock = threading.Lock()
        self.angles = None
        self.states_t, self._history = [], collections.deque(maxlen=STILL_SETS)
        self.statuses = [None] * settings.NUM_JOINTS
        self.button = None
        self.teleop, self.teleop_log = None, []
        self.diag, self.diag_status = {}, None
        self._hand = rospy.Publisher('%s/%s' % (sim, interface.SIM_HAND), JointState,
                                     queue_size=10, latch=True)
        self._button = rospy.Publisher('%s/%s' % (sim, interface.SIM_BUTTON), UInt8,
                                       queue_size=10, latch=True)
        self._grippers = rospy.Publisher('%s/%s' % (sim, interface.SIM_GRIPPERS),
                                         Float32MultiArray, queue_size=10, latch=True)
        self._opmode = rospy.Publisher('%s/%s' % (ns, interface.OPMODE), String, queue_size=10)
        rospy.Subscriber('%s/%s' % (ns, interface.JOINT_STATES), JointState, self._on_states,
                         queue_size=100)
        rospy.Subscriber('%s/%s' % (ns, interface.TELEOP_STATE), TeleopState, self._on_teleop,
                         queue_size=10)
        rospy.Subscriber('%s/%s' % (ns, interface.USER_BUTTON), UInt8, self._on_button,
                         queue_size=10)
        rospy.Subscriber(interface.DIAGNOSTICS, DiagnosticArray, self._on_diag, queue_size=100)
        for j in settings.JOINTS:
            rospy.Subscriber(interface.joint_topic(side, j, 'enc_stat'), String, self._on_status,
                             callback_args=j, queue_size=10)

    def _on_states(self, msg):
        with self._lock:
            self.angles = list(msg.position)
            self.states_t.append(time.monotonic())
            self._history.append(list(msg.position))

    def _on_status(self, msg, joint):
        self.statuses[joint] = msg.data

    def _on_button(self, msg):
        self.button = msg.data

    def _on_teleop(self, msg):
        with self._lock:
            self.teleop = msg
            self.teleop_log.append((time.monotonic(), msg))

    def _on_diag(self, msg):
        for status in msg.status:
            if (status.hardware_id == interface.puppet_ns(self.side)
                    and status.name.endswith(interface.DIAG_TELEOP)):
                self.diag = {kv.key: kv.value for kv in status.values}
                self.diag_status = status

    def hand(self, pose):
        """Move the operator's hand to pose (7 rad; NaN lets go of a joint)."""
        self._hand.publish(JointState(name=list(settings.JOINT_NAMES), position=list(pose)))

    def press(self, button, timeout_s=10.0):
        """Press a user button until the puppet reports it, then let go until it reports none."""
        for reading in (button, 0):
            self._button.publish(UInt8(reading))
            wait_for(lambda: self.button == reading, timeout_s,
                     'puppet %s reporting button %d' % (self.side, reading))

    def set_opmode(self, mode):
        """Set the opmode on <ns>/opmode as the GUI does (limp, hold or feel)."""
        self._opmode.publish(String(mode))

    def end_piece(self, pressed):
        self._grippers.publish(Float32MultiArray(data=PRESSED if pressed else RELEASED))

    def state(self):
        return None if self.teleop is None else self.teleop.state

    def sets_since(self, t):
        """Return how many joint_states arrived after monotonic time t."""
        with self._lock:
            return sum(1 for seen in self.states_t if seen > t)

    def wait_sets(self, count, timeout_s=10.0):
        """Wait until `count` more joint_states have arrived."""
        start = time.monotonic()
        wait_for(lambda: self.sets_since(start) >= count, timeout_s,
                 '%d joint_states from puppet %s' % (count, self.side))

    def reports_since(self, t):
        """Return the TeleopStates received after monotonic time t."""
        with self._lock:
            return [msg for seen, msg in self.teleop_log if seen > t]

    def wait_still(self, since_angles, timeout_s=15.0):
        """Wait until the puppet has moved away from since_angles and then holds still."""
        def moved_and_still():
            with self._lock:
                recent = list(self._history)
            return (len(recent) == STILL_SETS and max_error(recent[-1], since_angles) > 0.05
                    and all(max_error(a, recent[-1]) < STILL_RAD for a in recent))
        wait_for(moved_and_still, timeout_s, 'puppet %s moved and still' % self.side)


class Baxter:
    """What Baxter (the stand-in) does and is told."""

    def __init__(self):
        self._lock = threading.Lock()
        self.position = {}
        self.commands = {side: [] for side in interface.BAXTER_SIDES}  # (time, names, command)
        self.gripper = {}
        self.names = {side: baxter_description.arm_joint_names(side)
                      for side in interface.BAXTER_SIDES}
        self.limits = {side: baxter_description.arm_limits(side)
                       for side in interface.BAXTER_SIDES}
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on_joints,
                         queue_size=10)
        for side in interface.BAXTER_SIDES:
            rospy.Subscriber(interface.limb_topic(side, 'joint_command'), JointCommand,
                             self._on_command, callback_args=side, queue_size=1000)
            rospy.Subscriber(interface.baxter_gripper_topic(side, 'state'), EndEffectorState,
                             self._on_gripper, callback_args=side, queue_size=10)

    def _on_joints(self, msg):
        with self._lock:
            self.position.update(zip(msg.name, msg.position))

    def _on_command(self, msg, side):
        with self._lock:
            self.commands[side].append((time.monotonic(), list(msg.names), list(msg.command)))

    def _on_gripper(self, msg, side):
        self.gripper[side] = msg

    def arm(self, side):
        with self._lock:
            return [self.position.get(name, math.nan) for name in self.names[side]]

    def commands_since(self, side, t):
        """Return the commands (time, names, command) to `side` received after time t."""
        with self._lock:
            return [c for c in self.commands[side] if c[0] > t]


def calibrate(puppet, pose):
    """Sweep the quadrature joints through their index marks, ending the hand at `pose`."""
    first = list(pose)
    for j in settings.QUAD_JOINTS:
        first[j] = -0.4 if pose[j] >= 0 else 0.4
    wait_for(lambda: puppet.angles is not None, 30, 'joint_states from puppet %s' % puppet.side)
    start = list(puppet.angles)
    puppet.hand(first)
    puppet.wait_still(start)
    puppet.hand(pose)
    wait_for(lambda: puppet.statuses == [interface.WORKING] * settings.NUM_JOINTS, 15,
             'all joints of puppet %s Working (now %s)' % (puppet.side, puppet.statuses))


def node_pid(name):
    """Return the process id of a running ROS node, asked through its own XML-RPC API."""
    uri = rosgraph.Master(rospy.get_name()).lookupNode(name)
    code, message, pid = xmlrpc.client.ServerProxy(uri).getPid(rospy.get_name())
    if code != 1:
        raise AssertionError('cannot get the pid of %s: %s' % (name, message))
    return pid


@contextlib.contextmanager
def swinging_hand(puppet, pose, joint=3, amplitude_rad=0.5, rate_rad_s=2.5):
    """Swing one joint of the operator's hand around pose (a sine at up to amplitude x rate
    rad/s, faster than Baxter's default mode-1 speed on e1) until the block ends."""
    stop = threading.Event()

    def swing():
        t0 = time.monotonic()
        while not stop.is_set():
            moved = list(pose)
            moved[joint] = pose[joint] + amplitude_rad * math.sin(
                rate_rad_s * (time.monotonic() - t0))
            puppet.hand(moved)
            stop.wait(0.02)  # the hand's pace, not a wait for anything

    mover = threading.Thread(target=swing, daemon=True)
    mover.start()
    try:
        yield
    finally:
        stop.set()
        mover.join()
