"""Watch a puppet arm track the setpoints of a playback, from what it reports itself.

Pure: no rospy, time (s) is an argument; angles in rad, voltages in V. The puppet reports each
joint's angle and its PID voltage (joint_states: position, effort) at its state rate (10 Hz in
the 2020 firmware); the voltage is the PID output clamped to [voltage_min, voltage_max], so a
motor pushing as hard as it may reports its limit. Rules, each ending the playback with the
joints named, how far, for how long and at what voltage:

- not following: a joint more than FOLLOW_ERROR_RAD from its setpoint while its motor is
  saturated, in every sample for FOLLOW_TIME_S;
- saturated too long: a motor saturated in every sample for SATURATION_MAX_S, however close
  its joint (it pushes against something: protect the motor);
- the end: the puppet measured within FINAL_TOLERANCE_RAD of the last setpoints on every joint
  (a sample taken at or after they were sent), else not reached FINAL_TIMEOUT_S after them.

Why these numbers, for the shipped gains (pid_kp 20 V/rad, pid_ki 10 V/(rad s), pid_kd 1) and
the firmware's 50 Hz PID clamped at +-7.2 V (the motor supply):
- The simulated puppet (its arm physics and firmware, tests/unit/test_tracking_watch.py) moved
  0.5 or 1.1 rad on every joint at the playback's top setpoint speed (1.5 rad/s), from three
  poses, let go or under a resting hand: the error seen at its 10 Hz state sets peaks at
  0.34 rad (the setpoint moves on while a state set travels) and no motor saturates at all.
  Held firmly, every motor saturates within 0.25 s and stays there.
- Saturated, a motor pushes as hard as it can: kp alone asks 6 V at 0.3 rad, and a servo at
  full voltage turns at up to 7 rad/s, so a joint still more than 0.3 rad behind after a whole
  second at its limit is held or blocked (a hand, a table, its stop): FOLLOW_ERROR_RAD 0.3,
  FOLLOW_TIME_S 1.0 (ten state sets, fifty PID ticks).
- A servo stalled at full voltage draws its stall current and heats: seconds do no harm, tens
  of seconds may. SATURATION_MAX_S 2.0, twice the following rule's time, so that a joint far
  off is named by that rule first.
- After the last setpoint a joint loaded by gravity or held by friction settles as the integral
  wins (kp / ki = 2 s): the simulated puppet comes within 0.05 rad at most 2.2 s after its
  setpoints stop. FINAL_TOLERANCE_RAD 0.05 (3 degrees), FINAL_TIMEOUT_S 4.0.
- SATURATION_MARGIN_V: the voltage travels as a float32 (7.2 arrives as 7.1999998), and a PID
  a hair under its clamp pushes as hard as at it.
"""
import collections
import math

from robopuppet import settings

FOLLOW_ERROR_RAD = 0.3      # this far from its setpoint, saturated ...
FOLLOW_TIME_S = 1.0         # ... for this long: the joint does not follow
SATURATION_MAX_S = 2.0      # a motor saturated this long, however close: protect it
SATURATION_MARGIN_V = 0.05  # within this of its voltage limit a motor is saturated
FINAL_TOLERANCE_RAD = 0.05  # the last pose is reached when every joint is this close ...
FINAL_TIMEOUT_S = 4.0       # ... within this long after the last setpoints went out
_TIE_S = 1e-9               # durations are sums of sample periods

Verdict = collections.namedtuple('Verdict', 'joints why')
Verdict.__doc__ = 'A rule broken: the joints it names (sorted) and why, in words.'


def voltage_limits(stored):
    """Return the 7 (voltage_min, voltage_max) V of stored settings {joint: {name: value}};
    None: the defaults (the motor supply, +-7.2 V)."""
    values = stored or {j: settings.DEFAULTS for j in settings.JOINTS}
    return [(values[j]['voltage_min'], values[j]['voltage_max']) for j in settings.JOINTS]


def saturated(volts, lower_v, upper_v):
    """Return True when a PID voltage is at its clamp [lower_v, upper_v] (within the margin).

    A limit of 0 V is no push, and a voltage unknown (None, NaN) is not saturated."""
    if volts is None or not math.isfinite(volts):
        return False
    return ((upper_v > SATURATION_MARGIN_V and volts >= upper_v - SATURATION_MARGIN_V)
            or (lower_v < -SATURATION_MARGIN_V and volts <= lower_v + SATURATION_MARGIN_V))


def _wrap(angle_rad):
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


class TrackingWatch:
    """Watch one puppet arm track its setpoints.

    Args:
        side: the puppet side, 'L' or 'R' (for the messages).
        limits: 7 (voltage_min, voltage_max) V the device clamps its PIDs to (voltage_limits()).
    """

    def __init__(self, side, limits):
        self.side, self._limits = side, list(limits)
        n = settings.NUM_JOINTS
        self._far_since, self._saturated_since = [None] * n, [None] * n
        self._sample_t, self._angles, self._volts = None, None, [None] * n

    def on_sample(self, t, setpoints, angles, voltages=None):
        """Take a sample of the arm (7 angles rad, 7 voltages V or None) with the setpoints it
        was sent (7 rad); return a Verdict when a rule is broken, else None."""
        self._sample_t, self._angles = t, list(angles)
        self._volts = list(voltages) if voltages is not None else [None] * len(angles)
        errors = [abs(_wrap(a - s)) for a, s in zip(angles, setpoints)]
        hot = [saturated(v, *limit) for v, limit in zip(self._volts, self._limits)]
        for j, (error, pushing) in enumerate(zip(errors, hot)):
            far = pushing and error > FOLLOW_ERROR_RAD
            self._far_since[j] = (self._far_since[j] if self._far_since[j] is not None
                                  else t) if far else None
            self._saturated_since[j] = (self._saturated_since[j] if self._saturated_since[j]
                                        is not None else t) if pushing else None
        if any(_lasted(since, t, FOLLOW_TIME_S) for since in self._far_since):
            joints = [j for j, since in enumerate(self._far_since) if since is not None]
            return Verdict(joints, 'puppet arm %s does not follow: %s (saturated)' % (
                self.side, ', '.join('joint %d %.2f rad from its setpoint for %.1f s at %s' % (
                    j, errors[j], t - self._far_since[j], self._volt_text(j)) for j in joints)))
        joints = [j for j, since in enumerate(self._saturated_since)
                  if _lasted(since, t, SATURATION_MAX_S)]
        if joints:
            return Verdict(joints, 'puppet arm %s pushes at its voltage limit too long: %s '
                           '(to protect the motors)' % (self.side, ', '.join(
                               'joint %d at %s for %.1f s, %.2f rad from its setpoint' % (
                                   j, self._volt_text(j), t - self._saturated_since[j],
                                   errors[j]) for j in joints)))
        return None

    def reached(self, target, since_t):
        """Return True when a sample taken at or after since_t has every joint within
        FINAL_TOLERANCE_RAD of target (7 rad)."""
        return (self._sample_t is not None and self._sample_t >= since_t - _TIE_S
                and all(e <= FINAL_TOLERANCE_RAD for e in self._errors(target)))

    def not_reached(self, target, waited_s):
        """Return the Verdict of an arm that has not reached target (7 rad) waited_s after its
        last setpoints went out."""
        errors = self._errors(target)
        joints = [j for j, e in enumerate(errors) if e > FINAL_TOLERANCE_RAD]
        if not joints:  # there, but measured before the last setpoints went out
            return Verdict(list(settings.JOINTS), 'puppet arm %s sent no joint states in the '
                           '%.1f s after the last setpoints' % (self.side, waited_s))
        return Verdict(joints, 'puppet arm %s did not reach the last recorded pose within '
                       '%.2f rad %.1f s after the last setpoints: %s' % (
                           self.side, FINAL_TOLERANCE_RAD, waited_s, ', '.join(
                               'joint %d %.2f rad from it at %s' % (j, errors[j],
                                                                    self._volt_text(j))
                               for j in joints)))

    def distance(self, target):
        """Return the largest distance (rad) of the last sample's joints from target."""
        return max(self._errors(target))

    def _errors(self, target):
        if self._angles is None:
            return [math.inf] * len(target)
        return [abs(_wrap(a - s)) for a, s in zip(self._angles, target)]

    def _volt_text(self, joint):
        volts = self._volts[joint]
        return 'an unknown voltage' if volts is None else '%.2f V' % volts


def _lasted(since, t, duration_s):
    """Return True when a condition true in every sample since `since` has lasted duration_s."""
    return since is not None and t - since >= duration_s - _TIE_S
