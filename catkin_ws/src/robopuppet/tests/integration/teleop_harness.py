"""Operator's hand and observer for end-to-end tests of main_sim.launch (imported by the tests).

Plays the operator through the simulated puppet's operator topics (/puppet_sim/arm_X/...) and
records what the puppet reports and what Baxter is told and does, with reception times.
"""
import contextlib
import math
import threading
import time
import xmlrpc.client

import rosgraph
import rospy
from baxter_core_msgs.msg import EndEffectorState, JointCommand
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, String, UInt8

from robopuppet import baxter_description
from robopuppet.arm import teleop
from robopuppet_msgs.msg import TeleopState

RELEASED = [0.0, 0.0, 0.0, 1.0]   # gripper readings with the end-piece button released
PRESSED = [0.0, 0.0, 0.0, 0.0]
QUAD_JOINTS = (0, 2, 4, 6)


class PuppetArm:
    """One simulated puppet arm: the operator's side of it and what it reports."""

    def __init__(self, side):
        self.side = side
        sim = '/puppet_sim/arm_%s/' % side
        ns = '/puppet/arm_%s/' % side
        self._lock = threading.Lock()
        self.angles = None
        self.states_t = []
        self.statuses = [None] * 7
        self.teleop = None
        self._hand = rospy.Publisher(sim + 'hand', JointState, queue_size=10, latch=True)
        self._button = rospy.Publisher(sim + 'button', UInt8, queue_size=10, latch=True)
        self._grippers = rospy.Publisher(sim + 'grippers', Float32MultiArray, queue_size=10,
                                         latch=True)
        rospy.Subscriber(ns + 'joint_states', JointState, self._on_states, queue_size=100)
        rospy.Subscriber(ns + 'teleop_state', TeleopState, self._on_teleop, queue_size=10)
        for j in range(7):
            rospy.Subscriber(ns + 'joint_%d/enc_stat' % j, String, self._on_status,
                             callback_args=j, queue_size=10)

    def _on_states(self, msg):
        with self._lock:
            self.angles = list(msg.position)
            self.states_t.append(time.monotonic())

    def _on_status(self, msg, joint):
        self.statuses[joint] = msg.data

    def _on_teleop(self, msg):
        self.teleop = msg

    def hand(self, pose):
        """Move the operator's hand to pose (7 rad; NaN lets go of a joint)."""
        self._hand.publish(JointState(name=['joint_%d' % j for j in range(7)],
                                      position=list(pose)))

    def press(self, button, hold_s=0.4):
        """Press a user button and let it go."""
        self._button.publish(UInt8(button))
        time.sleep(hold_s)
        self._button.publish(UInt8(0))
        time.sleep(0.2)

    def end_piece(self, pressed):
        self._grippers.publish(Float32MultiArray(data=PRESSED if pressed else RELEASED))

    def state(self):
        return None if self.teleop is None else self.teleop.state


class Baxter:
    """What Baxter (the stand-in) does and is told."""

    def __init__(self):
        self._lock = threading.Lock()
        self.position = {}
        self.commands = {side: [] for side in teleop.SIDES}  # (time, names, command)
        self.gripper = {}
        self.names = {side: baxter_description.arm_joint_names(side) for side in teleop.SIDES}
        self.limits = {side: baxter_description.arm_limits(side) for side in teleop.SIDES}
        rospy.Subscriber('/robot/joint_states', JointState, self._on_joints, queue_size=10)
        for side in teleop.SIDES:
            rospy.Subscriber('/robot/limb/%s/joint_command' % side, JointCommand,
                             self._on_command, callback_args=side, queue_size=1000)
            rospy.Subscriber('/robot/end_effector/%s_gripper/state' % side, EndEffectorState,
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


def wait_for(condition, timeout_s, what):
    """Wait until condition() is true; raise AssertionError naming `what` after timeout_s."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if condition():
            return
        time.sleep(0.05)
    raise AssertionError('timed out after %.0f s waiting for %s' % (timeout_s, what))


def max_error(a, b):
    return max(abs(x - y) for x, y in zip(a, b))


def calibrate(puppet, pose):
    """Sweep the quadrature joints through their index marks, ending the hand at `pose`."""
    first = list(pose)
    for j in QUAD_JOINTS:
        first[j] = -0.4 if pose[j] >= 0 else 0.4
    puppet.hand(first)
    time.sleep(1.0)
    puppet.hand(pose)
    wait_for(lambda: puppet.statuses == ['Working'] * 7, 15,
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
            time.sleep(0.02)

    mover = threading.Thread(target=swing, daemon=True)
    mover.start()
    try:
        yield
    finally:
        stop.set()
        mover.join()
