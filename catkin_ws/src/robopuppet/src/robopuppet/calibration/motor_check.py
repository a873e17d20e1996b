"""The sign_motor check in hold mode: does each joint's motor push toward its setpoint?

Pure: no ROS, no Qt, no clock (time t in s is passed in). Angles in rad, voltages in V.

For each joint in turn: every other joint's PID voltage is limited to 0 V and this joint's to
+-SAFE_VOLTAGE_V (voltage_min and voltage_max, every joint in one request), the puppet holds
its current angles, the joint's setpoint moves STEP_RAD up (down when that would pass
angle_max), and the reported angle shows the sign: toward the setpoint, sign_motor is right;
away from it, wrong; neither within WATCH_S, unknown (the joint is held, or carries more weight
than the safe voltage lifts: let the arm hang down). Then limp. At the end, on a failure and on
cancel the stored voltage limits of every joint come back (restore_values).

The adapter runs a MotorCheck by calling update(t, angles, voltages) with every reading and
doing the Command it returns, reporting each store with stored(t, error).
"""
import collections
import math

from robopuppet import settings
from robopuppet.calibration import solver

SAFE_VOLTAGE_V = 1.5
VOLTAGE_MARGIN_V = 0.1  # a reported PID voltage above SAFE + this: the limit is not in force
STEP_RAD = 0.2
MOVED_RAD = 0.05  # a move this large, either way, tells the direction
LOAD_S = 1.0  # after a store, before hold: serial_X loads the stored limits into the puppet
HOLD_S = 0.5  # in hold at the current angles before the step
WATCH_S = 4.0  # the joint must move within this time after the step
LIMITS = ('voltage_min', 'voltage_max')
OFF = {'voltage_min': 0.0, 'voltage_max': 0.0}
SAFE = {'voltage_min': -SAFE_VOLTAGE_V, 'voltage_max': SAFE_VOLTAGE_V}
RIGHT, WRONG, UNKNOWN = 'right', 'wrong', 'did not move'

Command = collections.namedtuple('Command', 'kind joint values')
Command.__doc__ = """What the adapter does now: kind 'store' (values: {joint: {name: value}},
one all-or-none request for all of them, then stored()), 'hold' (send the current angles as
setpoints, then hold), 'setpoint' (joint's setpoint to values, rad), 'limp', or 'wait'
(nothing)."""
WAIT = Command('wait', None, None)


class MotorCheck:
    """Check sign_motor of `joints` one at a time (see the module docstring).

    Args:
        stored: {joint: {setting name: value}}, the settings stored now (their voltage limits
            come back at the end).
        joints: the joints to check, in order.
    Attributes:
        results: {joint: RIGHT, WRONG or UNKNOWN}.
        error: '' or why the check stopped early.
        phase: 'store', 'load', 'hold', 'watch', 'restore' or 'done'.
    """

    def __init__(self, stored, joints=settings.JOINTS):
        self.joints = tuple(joints)
        self.original = {j: {n: stored[j][n] for n in LIMITS} for j in settings.JOINTS}
        self.signs = {j: stored[j]['sign_motor'] for j in settings.JOINTS}
        self._angle_max = {j: stored[j]['angle_max'] for j in settings.JOINTS}
        self._step_rad = STEP_RAD
        self.results = {}
        self.error = ''
        self.phase = 'store'
        self._since_s = None  # when the current phase began
        self._start_rad = None
        self._pending = None  # the next Command to hand out, once

    def joint(self):
        """Return the joint being checked, or None when none is (done or restoring)."""
        if self.phase in ('restore', 'done'):
            return None
        return next((j for j in self.joints if j not in self.results), None)

    def limits(self):
        """Return the {joint: voltage limits} to store for the joint being checked."""
        joint = self.joint()
        return {j: dict(SAFE if j == joint else OFF) for j in settings.JOINTS}

    def restore_values(self):
        """Return the {joint: voltage limits} stored before the check."""
        return {j: dict(v) for j, v in self.original.items()}

    def start(self):
        """Return the first Command: store the limits for the first joint."""
        self.phase = 'store'
        return Command('store', None, self.limits())

    def stored(self, t, error=''):
        """A store ended at t (s), with error '' or why it failed; return the next Command."""
        if self.phase == 'restore':
            self.phase = 'done'
            if error:
                self.error = (self.error + '; ' if self.error else '') + \
                    'restoring the voltage limits failed: %s' % error
            return WAIT
        if error:
            return self.abort('storing the safe voltage limits failed: %s' % error)
        self.phase, self._since_s = 'load', t
        return WAIT

    def cancel(self):
        """Stop now: return the Commands to limp and restore the stored limits."""
        return self.abort('cancelled')

    def abort(self, why):
        """Stop with an error; return limp now (the restore follows: see restore())."""
        self.error = why
        self.phase = 'restore'
        self._pending = Command('store', None, self.restore_values())
        return Command('limp', None, None)

    def update(self, t, angles_rad, voltages_v):
        """Take the reported angles (rad) and PID voltages (V) at t (s); return a Command."""
        if self._pending is not None:
            pending, self._pending = self._pending, None
            return pending
        joint = self.joint()
        if self.phase in ('hold', 'watch') and any(
                math.isfinite(v) and abs(v) > SAFE_VOLTAGE_V + VOLTAGE_MARGIN_V
                for v in voltages_v):
            return self.abort('the puppet drove %.2f V, above the safe %.1f V: the limits did '
                              'not reach it' % (max(abs(v) for v in voltages_v
                                                    if math.isfinite(v)), SAFE_VOLTAGE_V))
        if joint is None or self.phase in ('store', 'restore', 'done'):
            return WAIT
        if not math.isfinite(angles_rad[joint]):
            return WAIT
        if self.phase == 'load' and t - self._since_s >= LOAD_S:
            self.phase, self._since_s = 'hold', t
            return Command('hold', None, None)
        if self.phase == 'hold' and t - self._since_s >= HOLD_S:
            self.phase, self._since_s = 'watch', t
            self._start_rad = angles_rad[joint]
            up = self._start_rad + STEP_RAD <= self._angle_max[joint]
            self._step_rad = STEP_RAD if up else -STEP_RAD
            return Command('setpoint', joint, self._start_rad + self._step_rad)
        if self.phase == 'watch':  # moved > 0: toward the setpoint
            moved = solver.wrap(angles_rad[joint] - self._start_rad) * math.copysign(
                1.0, self._step_rad)
            if abs(moved) >= MOVED_RAD or t - self._since_s >= WATCH_S:
                self.results[joint] = UNKNOWN if abs(moved) < MOVED_RAD else \
                    RIGHT if moved > 0.0 else WRONG
                last = self.joint() is None
                self.phase = 'restore' if last else 'store'
                self._pending = Command('store', None,
                                        self.restore_values() if last else self.limits())
                return Command('limp', None, None)
        return WAIT

    def wrong(self):
        """Return the joints whose motor pushed away from the setpoint."""
        return [j for j, r in sorted(self.results.items()) if r == WRONG]

    def flips(self, joints):
        """Return the {joint: {'sign_motor': flipped}} that corrects the given joints."""
        return {j: {'sign_motor': -self.signs[j]} for j in joints}
