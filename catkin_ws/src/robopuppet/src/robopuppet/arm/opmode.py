"""The puppet's opmode as arm_X drives it: limp, hold or feel (pure: time is an argument).

Button 1 cycles limp -> hold -> feel -> limp. The firmware holds whatever setpoints it has (0 rad
after a limp), so every way into hold or feel that arm_X takes sends the setpoints first, then
the opmode: hold goes to Baxter's measured pose of the arm on the puppet's side, feel to the feel
pose. Others set the opmode on <ns>/opmode too (the GUI; serial_X's feel watchdog sends limp):
arm_X adopts what they set (on_opmode), so that the next press goes on from the mode the puppet
is in; but a hold that another node set (the GUI's Hold, a playback into the puppet, which stops
on this very press) holds where that node put the puppet: the first press only makes the hold
arm_X's, with nothing sent, so that the puppet stays where it is; the next press goes on to feel.

Feel (docs/feel.md): the device holds with gentle gains (config_X's active settings) and
arm_X streams the feel pose as setpoints, one set per new puppet joint-state sample (so at the
state rate, not at the command rate): Baxter's measured pose of the arm this puppet drives,
mapped back into puppet joint space (joint_motion.driven_arm and in_puppet_space: as is on
the puppet's own side, mirrored on the other; when both arms or neither follow, its own side).
Where Baxter tracks the puppet the nurse feels almost nothing; where Baxter lags or is held back,
the puppet pulls toward where Baxter is.

Safety: feel ends in limp as soon as the teleop is in no state to stream (fault, no robot,
calibrating: an uncalibrated joint's angle is not where the setpoint would put it) or Baxter's
pose of that arm is missing or older than baxter_upkeep.ROBOT_TIMEOUT_S; hold ends in limp on a
fault (a silent puppet gets no setpoints). Baxter's poses come through BaxterWatch, which keeps
no non-finite or unbelievable pose, so such a value never becomes a setpoint.
"""
import collections
import reprlib

from robopuppet.arm.baxter_upkeep import ROBOT_TIMEOUT_S
from robopuppet.arm.joint_motion import driven_arm, in_puppet_space
from robopuppet.interface import FAULT, FEEL, FOLLOWING, HOLD, LIMP, OPMODES, READY

FEEL_STATES = (READY, FOLLOWING)   # the teleop states in which feel streams; any other: limp

SetOpmode = collections.namedtuple('SetOpmode', 'mode')
SetOpmode.__doc__ = 'Send the puppet opmode `mode` (limp, hold or feel).'
SetSetpoints = collections.namedtuple('SetSetpoints', 'angles')
SetSetpoints.__doc__ = 'Send the puppet seven joint setpoints (rad).'


class PuppetOpmode:
    """Keep the puppet's opmode and decide what arm_X sends the puppet for it.

    Args:
        own_side: Baxter's arm on the puppet's side, 'left' or 'right'.
        robot: the teleop's BaxterWatch (Baxter's measured poses).
    """

    def __init__(self, own_side, robot):
        self.own_side = own_side
        self.robot = robot
        self.mode = LIMP
        self._others_hold = False  # the hold is another node's (see the module's docstring)
        self._sample_t = None   # the puppet sample the newest feel setpoints answered

    def feel_pose(self, t, following):
        """Return (the feel pose: 7 puppet setpoints rad, '') or (None, why there is none).

        following: {side: whether Baxter's arm on that side follows this puppet}.
        """
        side = driven_arm(self.own_side, following['left'], following['right'])
        age_s = self.robot.pose_age(side, t)
        if age_s is None:
            return None, "no pose of Baxter's %s arm" % side
        if age_s > ROBOT_TIMEOUT_S:
            return None, "Baxter's %s arm pose is %.2f s old" % (side, age_s)
        return in_puppet_space(self.own_side, side, self.robot.pose[side]), ''

    def press(self, t, following, sample_t, actions):
        """Take a press of button 1 (cycle limp -> hold -> feel -> limp); append the actions.

        Return '' or why the press did not enter the next mode (to show in the detail). A hold
        needs Baxter's pose of the arm on the puppet's side (without it the press does nothing);
        a feel without a feel pose goes limp. sample_t: the newest puppet sample's time.
        """
        if self.mode == LIMP:
            pose = self.robot.pose.get(self.own_side)
            if pose is None:
                return "no hold: no pose of Baxter's %s arm yet" % self.own_side
            self._enter(HOLD, pose, actions)
        elif self.mode == HOLD and self._others_hold:
            self._others_hold = False
            return 'the hold is arm_X\'s now, where the puppet is; press 1 again for feel'
        elif self.mode == HOLD:
            pose, why = self.feel_pose(t, following)
            if pose is None:
                self._limp(actions)
                return 'no feel, the puppet goes limp: %s' % why
            self._enter(FEEL, pose, actions)
            self._sample_t = sample_t   # this sample is answered
        else:
            self._limp(actions)
        return ''

    def on_opmode(self, mode):
        """Adopt the opmode others set on <ns>/opmode (a repeat of the current one changes
        nothing); return '' or a warning to log when `mode` is no opmode (ignored)."""
        if mode not in OPMODES:
            return 'opmode must be one of %s, got %s; ignored' % ('/'.join(OPMODES),
                                                                  reprlib.repr(mode))
        if mode != self.mode:
            self.mode = mode
            self._others_hold = mode == HOLD
            self._sample_t = None   # into feel: the setpoints go out at the next step
        return ''

    def step(self, t, state, following, sample_t, actions):
        """Append what the puppet needs now in teleop state `state`; return '' or why the
        puppet goes limp (to add to the detail).

        In feel: SetSetpoints(feel pose) once per new puppet sample (sample_t: the newest
        one's time), or limp when the state or Baxter's pose does not allow feel. In hold: limp
        on a fault.
        """
        if self.mode == HOLD and state == FAULT:
            self._limp(actions)   # the detail says the fault already
            return ''
        if self.mode != FEEL:
            return ''
        if state not in FEEL_STATES:
            self._limp(actions)
            return 'feel ended (%s): the puppet goes limp' % state
        pose, why = self.feel_pose(t, following)
        if pose is None:
            self._limp(actions)
            return 'feel ended, the puppet goes limp: %s' % why
        if sample_t != self._sample_t:
            self._sample_t = sample_t
            actions.append(SetSetpoints(pose))
        return ''

    def _enter(self, mode, pose, actions):
        self.mode, self._others_hold = mode, False
        actions.append(SetSetpoints(list(pose)))
        actions.append(SetOpmode(mode))

    def _limp(self, actions):
        self.mode, self._others_hold = LIMP, False
        actions.append(SetOpmode(LIMP))
