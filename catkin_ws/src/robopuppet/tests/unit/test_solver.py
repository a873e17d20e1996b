"""The calibration solver: offsets anywhere on the circle (also near +-pi), both signs, noise,
a wrong pose flagged, and raw angles recovered from what the simulated firmware reports."""
import math
import random

import pytest

from robopuppet import settings
from robopuppet.calibration import procedure, solver
from robopuppet.puppet_sim.puppet_model import PuppetFirmware

NOISE_RAD = 0.005


def firmware_report(raw_rad, home_angle, sign_angle):
    """What the 2020 firmware reports (docs/serial.md), written out here as the test's oracle."""
    x = raw_rad - sign_angle * home_angle
    return sign_angle * math.atan2(math.sin(x), math.cos(x))


def circle_distance(a, b):
    return abs(math.atan2(math.sin(a - b), math.cos(a - b)))


def mounting(rng, count):
    """Return (signs, offsets): offsets in [-pi, pi), some at +-pi +- 0.01 rad."""
    edges = [math.pi - 0.01, -math.pi + 0.01, math.pi - 0.001 - 2 * math.pi, -math.pi]
    offsets = [edges[k] if k < len(edges) else rng.uniform(-math.pi, math.pi)
               for k in range(count)]
    return [rng.choice((1.0, -1.0)) for _ in range(count)], offsets


def captures(poses, signs, offsets, noise):
    """Raw encoder angles of a puppet with the given mounting in each pose, plus noise."""
    return [[(sign * q + c + noise()) for q, sign, c in zip(pose, signs, offsets)]
            for pose in poses]


@pytest.mark.parametrize('seed', range(30))
def test_offsets_and_signs_are_recovered_from_noisy_wizard_poses(seed):
    rng = random.Random(seed)
    signs, offsets = mounting(rng, settings.NUM_JOINTS)
    targets = [pose.angles_rad for pose in procedure.POSES]
    raws = captures(targets, signs, offsets, lambda: rng.uniform(-NOISE_RAD, NOISE_RAD))
    fits = solver.solve(targets, raws)
    for fit, sign, offset in zip(fits, signs, offsets):
        assert fit.sign_angle == sign, fit
        assert circle_distance(fit.home_angle, sign * offset) < 0.01, (fit, offset)
        assert -math.pi <= fit.home_angle < math.pi
        assert fit.problem == '' and fit.residual_rad < 2 * NOISE_RAD
        for pose in targets:  # the puppet then reports Baxter's angles
            raw = sign * pose[fit.joint] + offset
            assert abs(firmware_report(raw, fit.home_angle, fit.sign_angle)
                       - pose[fit.joint]) < 0.01


@pytest.mark.parametrize('seed', range(10))
def test_gaussian_noise_over_more_poses(seed):
    rng = random.Random(100 + seed)
    signs, offsets = mounting(rng, settings.NUM_JOINTS)
    targets = [[rng.uniform(-1.0, 1.0) for _ in settings.JOINTS] for _ in range(8)]
    fits = solver.solve(targets, captures(targets, signs, offsets,
                                          lambda: rng.gauss(0.0, NOISE_RAD)))
    assert [fit.sign_angle for fit in fits] == signs
    assert all(circle_distance(f.home_angle, s * c) < 0.01
               for f, s, c in zip(fits, signs, offsets))


def test_a_wrong_pose_is_flagged_by_its_residual():
    rng = random.Random(7)
    signs, offsets = mounting(rng, settings.NUM_JOINTS)
    targets = [pose.angles_rad for pose in procedure.POSES]
    raws = captures(targets, signs, offsets, lambda: rng.uniform(-NOISE_RAD, NOISE_RAD))
    raws[2][4] += 0.3  # joint 4 was 0.3 rad off in the third pose
    fits = solver.solve(targets, raws)
    assert fits[4].problem and fits[4].worst_pose == 2
    assert 'pose 3' in fits[4].problem
    assert [f.joint for f in fits if f.problem] == [4]


def test_a_joint_that_does_not_move_has_no_sign():
    fit = solver.fit_joint(0, [0.1, 0.1, 0.15], [1.0, 1.0, 1.05])
    assert 'sign cannot be told' in fit.problem


def test_too_few_poses_are_refused():
    with pytest.raises(solver.SolveError):
        solver.fit_joint(0, [0.0], [1.0])
    with pytest.raises(solver.SolveError):
        solver.solve([[0.0] * 7, [0.5] * 7], [[0.0] * 7])


@pytest.mark.parametrize('home, sign', [(0.0, 1.0), (2.9, -1.0), (-3.1, 1.0), (1.0, -1.0)])
def test_raw_angles_are_recovered_from_the_simulated_firmware(home, sign):
    """The simulated 2020 firmware's reported angle, undone with its settings, gives the
    encoder's raw angle (the hall joint 1: raw is the mechanical angle)."""
    firmware = PuppetFirmware()
    for name, value in (('sign_angle', sign), ('home_angle', home), ('angle_min', -math.pi),
                        ('angle_max', math.pi), ('velocity_min', -100.0),
                        ('velocity_max', 100.0)):
        firmware.configure(1, settings.CONFIG_ID[name], value)
    for k, hand in enumerate((-2.0, 0.3, 1.4, 3.0)):
        firmware.set_hand({1: hand})
        for step in range(1, 301):  # 3 s: the hand brings the joint to rest
            firmware.advance(3.0 * k + 0.01 * step)
        raw = solver.raw_from_reported(firmware.angle_rad[1], home, sign)
        assert circle_distance(raw, firmware.arm.angle_rad[1]) < 2e-3
        assert abs(solver.reported_from_raw(raw, home, sign) - firmware.angle_rad[1]) < 1e-9
