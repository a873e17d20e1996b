"""Keeping Baxter ready to follow: is it there, when to ask it to enable, when to calibrate its
grippers, and its gripper commands (pure: time in s is an argument, the node sends them).
"""
import collections
import json

from robopuppet.interface import BAXTER_SIDES

ROBOT_TIMEOUT_S = 1.0            # Baxter is absent when /robot/state or its joint states are older
ENABLE_PERIOD_S = 1.0            # how often to ask an absent or disabled Baxter to enable
GRIPPER_CALIBRATE_RETRY_S = 3.0  # a gripper still uncalibrated this long after a calibrate: resend
# Baxter's gripper API (baxter_core_msgs/EndEffectorCommand and EndEffectorState constants).
CMD_GO, CMD_CALIBRATE = 'go', 'calibrate'
POSITION_CLOSED, POSITION_OPEN = 0.0, 100.0  # percent of the gripper's travel

GripperCommand = collections.namedtuple('GripperCommand', 'side id command args sequence')
GripperCommand.__doc__ = """An EndEffectorCommand for Baxter's gripper on `side`: its id, the
command (CMD_GO or CMD_CALIBRATE), JSON args, and a sequence number that rises by one each."""


class BaxterUpkeep:
    """Follow Baxter's /robot/state, joint states and gripper states; say what to send it.

    Safety: calibrating an electric gripper opens it. A gripper is calibrated (as the Rethink SDK
    does: it ignores 'go' until calibrated, as after power-up) only until it has reported
    calibrated once since the start, so a garbage or glitched state later never drops what it
    holds, and never while it follows the puppet closed.
    Attributes:
        gripper_id: {side: the gripper's id in its newest state (0 while unknown)}, which its
            commands carry.
    """

    def __init__(self):
        self._enabled = False
        self._state_t = self._joints_t = None   # receipt times of /robot/state, joint states
        self._enable_t = None                   # when enabling was last asked for
        self.gripper_id = {side: 0 for side in BAXTER_SIDES}
        self._calibrated = {side: False for side in BAXTER_SIDES}  # seen calibrated once
        self._calibrate_t = {side: None for side in BAXTER_SIDES}
        self._sequence = 0

    def on_robot_state(self, t, enabled, stopped, error):
        """Take /robot/state's flags, received at time t."""
        self._enabled = enabled and not stopped and not error
        self._state_t = t

    def on_robot_joints(self, t):
        """Take the receipt of Baxter's joint states at time t."""
        self._joints_t = t

    def ready(self, t):
        """Return whether Baxter is present (both its state and joint states are fresh) and
        enabled (not stopped, no error) at time t."""
        present = all(seen is not None and t - seen < ROBOT_TIMEOUT_S
                      for seen in (self._state_t, self._joints_t))
        return present and self._enabled

    def enable_due(self, t):
        """Return whether to ask Baxter to enable now: while it is not ready, once per
        ENABLE_PERIOD_S (a True answer counts as asked)."""
        if self.ready(t) or (self._enable_t is not None and t - self._enable_t <= ENABLE_PERIOD_S):
            return False
        self._enable_t = t
        return True

    def on_gripper_state(self, t, side, gripper_id, calibrated, holding):
        """Take a gripper state; return the GripperCommand to calibrate it now, or None.

        Args:
            t: receipt time (s).
            side: 'left' or 'right'.
            gripper_id: the id in the state (0: no gripper).
            calibrated: whether the state says calibrated.
            holding: whether that arm follows the puppet with its gripper closed.
        """
        if gripper_id:
            self.gripper_id[side] = gripper_id  # as the Rethink SDK takes it, from the state
        if calibrated:
            self._calibrated[side] = True
        last_t = self._calibrate_t[side]
        if (self._calibrated[side] or holding or not gripper_id
                or (last_t is not None and t - last_t <= GRIPPER_CALIBRATE_RETRY_S)):
            return None
        self._calibrate_t[side] = t
        return self._command(side, CMD_CALIBRATE, {})

    def grip(self, side, close):
        """Return the GripperCommand that closes (close=True) or opens the gripper on `side`."""
        return self._command(side, CMD_GO, {'position': POSITION_CLOSED if close
                                            else POSITION_OPEN})

    def _command(self, side, command, args):
        self._sequence += 1
        return GripperCommand(side, self.gripper_id[side], command, json.dumps(args),
                              self._sequence)
