"""The learners' input: the leader arm's pose and a smoothed velocity, made the same way from a
recorded demonstration and from the live leader, and scaled to unit spread.

Pure (numpy): time comes in as an argument. A feature vector is the leader's 7 joint angles
(rad) followed by its 7 joint velocities (rad/s), each through a first-order low-pass filter of
time constant velocity_tau_s; both are then scaled by the training data's mean and spread. The
velocity tells apart the two ways along the same path (reaching out, bringing back), which a
pose alone cannot.
"""
import collections

import numpy as np

JOINTS = 7
SETTINGS = {
    'velocity_tau_s': 0.1,  # low-pass of the velocity: smooths 100 Hz finite differences
    'gap_s': 0.2,           # a longer step between poses restarts the filter (velocity 0)
    'position_floor_rad': 0.05,   # least spread a joint's angle is scaled by
    'velocity_floor_rad_s': 0.1,  # least spread a joint's velocity is scaled by
}

Scaling = collections.namedtuple('Scaling', 'x_mean x_scale y_mean y_scale')
Scaling.__doc__ = """Affine maps to unit spread: x_std = (x - x_mean) / x_scale, the same for
the outputs y (7 follower joints, then the gripper's 0 open .. 1 closed)."""


class VelocityFilter:
    """Turn a stream of (t, pose) into feature vectors [pose, smoothed velocity].

    Args:
        settings: SETTINGS' keys (velocity_tau_s, gap_s).
    """

    def __init__(self, settings=None):
        settings = dict(SETTINGS, **(settings or {}))
        self._tau_s = float(settings['velocity_tau_s'])
        self._gap_s = float(settings['gap_s'])
        self.reset()

    def reset(self):
        """Forget the past: the next pose starts with velocity 0."""
        self._t = None
        self._q = None
        self._v = np.zeros(JOINTS)

    def step(self, t, positions):
        """Return the features (14,) after the pose measured at t (s).

        A pose at the time of the last one (the same measurement again) changes nothing; one
        more than gap_s after it restarts the filter.
        """
        q = np.asarray(positions, float)
        if self._t is None or t - self._t > self._gap_s or t < self._t:
            self._v = np.zeros(JOINTS)
        elif t > self._t:
            dt = t - self._t
            alpha = 1.0 - np.exp(-dt / self._tau_s)
            self._v = self._v + alpha * ((q - self._q) / dt - self._v)
        else:
            return np.concatenate([self._q, self._v])
        self._t, self._q = t, q
        return np.concatenate([q, self._v])


def sequence_features(t, leader, settings=None):
    """Return the features (N, 14) of a leader's poses (N, 7) at times t (N,), s, as a
    VelocityFilter stepped through them gives them (gaps restart it)."""
    velocity_filter = VelocityFilter(settings)
    return np.array([velocity_filter.step(t_k, q_k) for t_k, q_k in zip(t, leader)]).reshape(
        len(t), 2 * JOINTS)


def outputs(follower, closed):
    """Return the learners' outputs (N, 8): the follower's 7 angles and its gripper (1 closed)."""
    return np.column_stack([np.asarray(follower, float), np.asarray(closed, float)])


def fit_scaling(x, y, settings=None):
    """Return the Scaling of training inputs x (N, 14) and outputs y (N, 8): mean and standard
    deviation per column, the input's with a floor so that a joint the demonstrations hardly
    move is not scaled up to noise."""
    settings = dict(SETTINGS, **(settings or {}))
    floor = np.r_[np.full(JOINTS, settings['position_floor_rad']),
                  np.full(JOINTS, settings['velocity_floor_rad_s'])]
    return Scaling(x.mean(axis=0), np.maximum(x.std(axis=0), floor),
                   y.mean(axis=0), np.maximum(y.std(axis=0), 1e-3))
