"""The operator's hands on simulated puppets, each posed to show a wanted Baxter arm pose.

The puppet that drives Baxter arm S is the one on S's side (puppet L for Baxter's left, R for
its right), whose own-side arm copies its angles. The hand sets mechanical angles: the puppet
reports sign_angle x (raw - sign_angle x home_angle) (puppet_sim's encoders), so the hand takes
sign x (angle + home), with the shipped ini files' home 0 and sign +1 unless told otherwise.
"""
import threading
import time

import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, UInt8

from robopuppet import interface, settings
from robopuppet_msgs.msg import TeleopState

PUPPET_SIDE = {'left': 'L', 'right': 'R'}
RELEASED = [1.0 if g == interface.END_PIECE_GRIPPER else 0.0
            for g in range(interface.NUM_GRIPPERS)]   # the end-piece button released
PRESSED = [0.0] * interface.NUM_GRIPPERS
FOLLOW_BUTTON = {'left': interface.BUTTON_LEFT, 'right': interface.BUTTON_RIGHT}
INDEX_SWING_RAD = 0.4   # calibrate() turns the quadrature joints through 0 from this far
STILL_S = 0.25          # a puppet whose angles do not change over this long stands still


class SimHandsError(RuntimeError):
    """A simulated puppet did not answer in time; the message says which and what."""


class SimHands:
    """Pose, grip and press the simulated puppets that drive Baxter's arms `sides`.

    Args:
        sides: Baxter sides ('left', 'right') whose puppets to drive.
        calibration: {side: (home_angle 7 rad, sign_angle 7 +-1)}; the shipped ini files'
            (0, +1) for a side not given.

    ROS API: publishes (latched) sim_ns(X)/hand, button, grippers; subscribes puppet_ns(X)/
    joint_states, user_btn and teleop_state, X the puppet side of each Baxter side.
    """

    def __init__(self, sides, calibration=None):
        self.sides = tuple(sides)
        self._calibration = {s: ([0.0] * 7, [1.0] * 7) for s in self.sides}
        self._calibration.update(calibration or {})
        self._lock = threading.Lock()
        self._angles, self._button, self._teleop = {}, {}, {}
        self._pubs = {}
        for side in self.sides:
            sim, ns = interface.sim_ns(PUPPET_SIDE[side]), interface.puppet_ns(PUPPET_SIDE[side])
            self._pubs[side] = {
                'hand': rospy.Publisher('%s/%s' % (sim, interface.SIM_HAND), JointState,
                                        queue_size=10, latch=True),
                'button': rospy.Publisher('%s/%s' % (sim, interface.SIM_BUTTON), UInt8,
                                          queue_size=10, latch=True),
                'grippers': rospy.Publisher('%s/%s' % (sim, interface.SIM_GRIPPERS),
                                            Float32MultiArray, queue_size=10, latch=True)}
            for name, kind, store in ((interface.JOINT_STATES, JointState, self._angles),
                                      (interface.USER_BUTTON, UInt8, self._button),
                                      (interface.TELEOP_STATE, TeleopState, self._teleop)):
                rospy.Subscriber('%s/%s' % (ns, name), kind, self._keep,
                                 callback_args=(store, side), queue_size=10)

    def _keep(self, msg, where):
        store, side = where  # (dict, side)
        with self._lock:
            store[side] = list(msg.position) if isinstance(msg, JointState) else msg

    def play(self, demo, sides=None):
        """Move the hands of `sides` (default all) through a demonstration.Demo at its own times,
        the grippers as it says; the other puppets stay as they are."""
        start, closed = time.monotonic(), {}
        for i, t_s in enumerate(demo.t):
            time.sleep(max(0.0, start + t_s - time.monotonic()))
            for side in sides or self.sides:
                self.pose(side, getattr(demo, side)[i])
                if closed.get(side) != getattr(demo, side + '_closed')[i]:
                    closed[side] = getattr(demo, side + '_closed')[i]
                    self.grip(side, closed[side])

    def connected(self, side):
        """Return True when the side's simulated puppet listens to the hand topic."""
        return self._pubs[side]['hand'].get_num_connections() > 0

    def angles(self, side):
        """Return the puppet's newest reported angles (7 rad), or None before any."""
        with self._lock:
            return self._angles.get(side)

    def teleop(self, side):
        """Return the newest TeleopState of the side's puppet's arm controller, or None."""
        with self._lock:
            return self._teleop.get(side)

    def pose(self, side, baxter_angles):
        """Move the hand so that the puppet shows Baxter arm `side` at baxter_angles (7 rad)."""
        home, sign = self._calibration[side]
        raw = [s * (a + h) for a, h, s in zip(baxter_angles, home, sign)]
        self._pubs[side]['hand'].publish(JointState(name=list(settings.JOINT_NAMES),
                                                    position=raw))

    def grip(self, side, closed):
        """Press (closed) or release the end-piece button of the side's puppet."""
        self._pubs[side]['grippers'].publish(
            Float32MultiArray(data=PRESSED if closed else RELEASED))

    def wait(self, condition, timeout_s, what):
        """Wait until condition() holds; raise SimHandsError naming `what` after timeout_s."""
        deadline = time.monotonic() + timeout_s
        while not condition():
            if time.monotonic() > deadline or rospy.is_shutdown():
                raise SimHandsError('no %s within %g s' % (what, timeout_s))
            time.sleep(0.02)

    def press(self, side, button, timeout_s=5.0):
        """Press user button 1-4 of the side's puppet until it reports it, then let go until it
        reports none (a press acts once)."""
        for reading in (button, 0):
            self._pubs[side]['button'].publish(UInt8(reading))
            self.wait(lambda: getattr(self._button.get(side), 'data', None) == reading,
                      timeout_s, 'button %d from puppet %s' % (reading, PUPPET_SIDE[side]))

    def near(self, side, baxter_angles, tolerance_rad, joints=settings.JOINTS):
        """Return True when the puppet reports `joints` within tolerance of baxter_angles."""
        angles = self.angles(side)
        return angles is not None and max(
            abs(angles[j] - baxter_angles[j]) for j in joints) <= tolerance_rad

    def calibrate(self, side, baxter_angles, timeout_s=15.0):
        """Turn the quadrature joints through their index marks, ending at baxter_angles.

        Until its index mark a quadrature joint reports an angle counted from power-on, so the
        first swing waits for the absolute joints to arrive and every joint to stand still.
        """
        first = list(baxter_angles)
        for j in settings.QUAD_JOINTS:
            first[j] = -INDEX_SWING_RAD if baxter_angles[j] >= 0 else INDEX_SWING_RAD
        self.pose(side, first)
        seen = [None]

        def still():
            before, seen[0] = seen[0], self.angles(side)
            time.sleep(STILL_S)
            return (before is not None and self.near(side, first, 0.05, settings.HALL_JOINTS)
                    and self.near(side, before, 1e-3))
        self.wait(still, timeout_s, 'puppet %s still at the index swing' % PUPPET_SIDE[side])
        self.pose(side, baxter_angles)
        self.wait(lambda: self.near(side, baxter_angles, 0.05), timeout_s,
                  'puppet %s at the pose' % PUPPET_SIDE[side])
