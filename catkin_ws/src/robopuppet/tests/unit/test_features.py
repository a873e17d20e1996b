"""The learners' features: the leader's pose and its low-pass filtered velocity."""
import numpy as np

from robopuppet.assist import features


def test_the_velocity_settles_on_a_steady_motions_speed():
    velocity_filter = features.VelocityFilter({'velocity_tau_s': 0.1})
    slope = np.arange(7) * 0.1 - 0.3
    for k in range(101):  # 1 s at 100 Hz: ten time constants
        x = velocity_filter.step(0.01 * k, 0.2 + slope * 0.01 * k)
    assert np.allclose(x[:7], 0.2 + slope)
    assert np.allclose(x[7:], slope, atol=1e-3)


def test_the_same_measurement_again_changes_nothing():
    velocity_filter = features.VelocityFilter()
    velocity_filter.step(0.0, np.zeros(7))
    first = velocity_filter.step(0.02, np.full(7, 0.01))
    again = velocity_filter.step(0.02, np.full(7, 0.01))
    assert np.all(np.isfinite(again)) and np.array_equal(first, again)


def test_a_gap_restarts_the_velocity():
    velocity_filter = features.VelocityFilter({'gap_s': 0.2})
    for k in range(20):
        velocity_filter.step(0.02 * k, np.full(7, 0.05 * k))
    after_gap = velocity_filter.step(0.38 + 0.5, np.full(7, 5.0))
    assert np.array_equal(after_gap[7:], np.zeros(7))


def test_a_sequence_gives_what_stepping_gives():
    t = np.r_[np.arange(0, 1, 0.02), np.arange(2, 3, 0.02)]
    leader = np.sin(np.outer(t, np.arange(1, 8)))
    velocity_filter = features.VelocityFilter()
    stepped = np.array([velocity_filter.step(a, b) for a, b in zip(t, leader)])
    assert np.allclose(features.sequence_features(t, leader), stepped)


def test_the_scaling_floors_a_joint_that_never_moves():
    x = np.zeros((100, 14))
    x[:, 0] = np.linspace(-1, 1, 100)
    scaling = features.fit_scaling(x, np.zeros((100, 8)))
    assert scaling.x_scale[1] == features.SETTINGS['position_floor_rad']
    assert scaling.x_scale[8] == features.SETTINGS['velocity_floor_rad_s']
    assert np.isclose(scaling.x_scale[0], x[:, 0].std())
