"""Solve a joint's home_angle and sign_angle from poses: least squares on the circle.

Pure: no ROS, no Qt, no clock. Angles in rad.

The puppet's firmware reports `sign_angle * wrap(raw - sign_angle * home_angle)` for a joint
whose encoder reads `raw` (docs/serial.md, "Encoders"). The encoder of a joint that is at
Baxter's angle q reads `raw = wrap(sigma * q + c)` for a sign sigma and offset c fixed by how
the encoder is mounted. With sign_angle = sigma and home_angle = sigma * c the puppet reports q.

The solver therefore works on raw angles: raw_from_reported() undoes the settings that were in
force when a pose was captured, fit_joint() finds sigma and c for one joint from every captured
pose by least squares of the wrapped residuals wrap(raw - sigma * q - c) (so an offset near
+-pi does not flip), and the residual tells whether the poses agree.
"""
import collections
import math

from robopuppet import settings

RESIDUAL_LIMIT_RAD = 0.03  # RMS residual above this: a pose was wrong or the encoder slips
MIN_SPREAD_RAD = 0.25  # a joint must move at least this much across the poses to tell its sign

JointFit = collections.namedtuple('JointFit', 'joint sign_angle home_angle residual_rad '
                                              'worst_pose problem')
JointFit.__doc__ = """One joint's solution: sign_angle (+-1.0), home_angle (rad, in [-pi, pi)),
residual_rad (RMS of the wrapped residuals over the poses), worst_pose (index of the pose with
the largest residual) and problem ('' when the fit can be trusted, else why not)."""


class SolveError(ValueError):
    """The captured poses cannot give a solution (too few, or of different lengths)."""


def wrap(angle_rad):
    """Return angle_rad wrapped to [-pi, pi)."""
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


def raw_from_reported(reported_rad, home_angle, sign_angle):
    """Return the encoder's raw angle (rad, wrapped) behind a reported angle.

    Args:
        reported_rad: what the puppet reported, sign_angle * wrap(raw - sign_angle * home).
        home_angle, sign_angle: the joint's settings loaded in the puppet at that time.
    """
    return wrap(sign_angle * reported_rad + home_angle * sign_angle)


def reported_from_raw(raw_rad, home_angle, sign_angle):
    """Return what the firmware reports for a raw encoder angle (the inverse of the above)."""
    return sign_angle * wrap(raw_rad - sign_angle * home_angle)


def _circular_fit(offsets_rad):
    """Return (c, residuals): the c minimising sum(wrap(offset - c)^2), near the circular mean."""
    c = math.atan2(sum(math.sin(d) for d in offsets_rad), sum(math.cos(d) for d in offsets_rad))
    for _ in range(3):  # Gauss-Newton on the wrapped residuals; the circular mean starts close
        residuals = [wrap(d - c) for d in offsets_rad]
        c = wrap(c + sum(residuals) / len(residuals))
    return c, [wrap(d - c) for d in offsets_rad]


def _rms(values):
    return math.sqrt(sum(v * v for v in values) / len(values))


def fit_joint(joint, targets_rad, raws_rad):
    """Return the JointFit of one joint from its target angles and the raw angles captured.

    Args:
        joint: the joint index (only reported back).
        targets_rad: Baxter's angle of the joint in each pose.
        raws_rad: the encoder's raw angle captured in each pose (raw_from_reported).
    Raises:
        SolveError: fewer than two poses, or lists of different lengths.
    """
    if len(targets_rad) != len(raws_rad) or len(targets_rad) < 2:
        raise SolveError('joint %d: need two or more poses with one raw angle each, got %d '
                         'targets and %d raw angles' % (joint, len(targets_rad), len(raws_rad)))
    fits = []
    for sign in (1.0, -1.0):
        c, residuals = _circular_fit([r - sign * q for q, r in zip(targets_rad, raws_rad)])
        fits.append((_rms(residuals), sign, c, residuals))
    fits.sort(key=lambda fit: fit[0])
    rms, sign, c, residuals = fits[0]
    worst = max(range(len(residuals)), key=lambda k: abs(residuals[k]))
    problem = ''
    if max(targets_rad) - min(targets_rad) < MIN_SPREAD_RAD:
        problem = ('the poses move it by less than %.2f rad: its sign cannot be told'
                   % MIN_SPREAD_RAD)
    elif rms > RESIDUAL_LIMIT_RAD:
        problem = ('residual %.3f rad above %.3f rad: pose %d (off by %.3f rad) was not as '
                   'shown, or the encoder slips' % (rms, RESIDUAL_LIMIT_RAD, worst + 1,
                                                    residuals[worst]))
    return JointFit(joint, sign, wrap(sign * c), rms, worst, problem)


def solve(targets, raws):
    """Return one JointFit per joint from captured poses.

    Args:
        targets: per pose, Baxter's seven joint angles (rad).
        raws: per pose, the seven raw encoder angles captured (rad).
    Raises:
        SolveError: fewer than two poses, or a pose without seven angles.
    """
    if len(targets) != len(raws):
        raise SolveError('%d target poses but %d captures' % (len(targets), len(raws)))
    if any(len(pose) != settings.NUM_JOINTS for pose in list(targets) + list(raws)):
        raise SolveError('every pose needs %d joint angles' % settings.NUM_JOINTS)
    return [fit_joint(j, [pose[j] for pose in targets], [pose[j] for pose in raws])
            for j in settings.JOINTS]
