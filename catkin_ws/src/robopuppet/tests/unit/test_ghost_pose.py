"""The ghost's joint angles: the puppet's mapped as arm_X maps them, or the real robot's."""
import math
import xml.etree.ElementTree as ET

import pytest

from robopuppet import baxter_description
from robopuppet.ghost.ghost_pose import REAL, GhostPose

SUFFIXES = ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')
MIRROR_SIGNS = (-1, 1, -1, 1, -1, 1, -1)  # the opposite arm negates shoulder s0, e0, w0, w2
PUPPET_NAMES = ['joint_%d' % j for j in range(7)]
TIMEOUT_S = 0.5
# A pose with joint 0 beyond both s0 limits (+-1.7017 rad) and joint 1 below s1's (-2.147).
POSE_R = [1.9, -2.5, 0.3, 1.0, -0.3, 0.6, 0.25]
POSE_L = [-0.4, 0.2, -0.1, 0.5, 0.2, -0.3, 0.1]


def urdf_limits():
    """Return {joint name: (lower, upper) rad} read straight from the URDF, not through the
    module under test's tables."""
    root = ET.parse(baxter_description.URDF_PATH).getroot()
    return {j.get('name'): (float(j.find('limit').get('lower')),
                            float(j.find('limit').get('upper')))
            for j in root.findall('joint') if j.find('limit') is not None}


LIMITS = urdf_limits()


def expected(side, angles, mirrored):
    """Return {ghost joint name: angle} of one Baxter arm taking the puppet's angles."""
    result = {}
    for suffix, sign, angle in zip(SUFFIXES, MIRROR_SIGNS, angles):
        name = '%s_%s' % (side, suffix)
        lower, upper = LIMITS[name]
        result['ghost/' + name] = min(max(sign * angle if mirrored else angle, lower), upper)
    return result


def real_states():
    """Return (names, positions) of a real robot standing still: head turned, grippers open."""
    names = ['head_pan', 'l_gripper_l_finger_joint', 'r_gripper_l_finger_joint',
             'torso_t0', 'head_nod']  # torso_t0 is fixed and head_nod unknown here: ignored
    names += ['%s_%s' % (s, x) for s in ('left', 'right') for x in SUFFIXES]
    return names, [0.3, 0.02, 0.01, 0.7, 0.2] + [0.05 * k for k in range(14)]


def make():
    movable = [n for n in LIMITS] + ['head_pan']
    limits = {s: baxter_description.arm_limits(s) for s in ('left', 'right')}
    ghost = GhostPose(limits, movable, TIMEOUT_S, 'ghost/')
    assert ghost.on_robot(*real_states()) == ''
    return ghost


def states(ghost, t):
    names, positions = ghost.joint_states(t)
    return dict(zip(names, positions))


def real_arm(side):
    names, positions = real_states()
    return {'ghost/' + n: p for n, p in zip(names, positions) if n.startswith(side + '_')}


def assert_arm(got, want):
    for name, angle in want.items():
        assert got[name] == pytest.approx(angle, abs=1e-12), name


def test_one_puppet_copies_its_own_side_and_mirrors_the_other_clamped_to_the_limits():
    ghost = make()
    assert ghost.on_puppet(1.0, 'R', PUPPET_NAMES, POSE_R) == ''
    got = states(ghost, 1.1)
    assert_arm(got, expected('right', POSE_R, mirrored=False))
    assert_arm(got, expected('left', POSE_R, mirrored=True))
    assert got['ghost/right_s0'] == pytest.approx(1.7017, abs=1e-4) and \
        got['ghost/left_s0'] == pytest.approx(-1.7017, abs=1e-4)  # clamped, after mirroring
    assert ghost.sources(1.1) == {'left': 'R', 'right': 'R'}


def test_two_puppets_each_show_their_own_side():
    ghost = make()
    ghost.on_puppet(1.0, 'R', PUPPET_NAMES, POSE_R)
    ghost.on_puppet(1.0, 'L', PUPPET_NAMES, POSE_L)
    got = states(ghost, 1.2)
    assert_arm(got, expected('left', POSE_L, mirrored=False))
    assert_arm(got, expected('right', POSE_R, mirrored=False))


def test_the_arm_a_puppet_follows_shows_that_puppet_even_against_the_other_side():
    ghost = make()
    ghost.on_puppet(1.0, 'R', PUPPET_NAMES, POSE_R)
    ghost.on_puppet(1.0, 'L', PUPPET_NAMES, POSE_L)
    ghost.on_teleop('R', follow_left=True, follow_right=False)
    got = states(ghost, 1.2)
    assert_arm(got, expected('left', POSE_R, mirrored=True))
    assert_arm(got, expected('right', POSE_R, mirrored=False))


def test_a_silent_puppet_leaves_the_ghost_on_the_real_robot():
    ghost = make()
    ghost.on_puppet(1.0, 'R', PUPPET_NAMES, POSE_R)
    ghost.on_teleop('R', follow_left=True, follow_right=True)
    assert ghost.sources(1.0 + TIMEOUT_S) == {'left': 'R', 'right': 'R'}
    got = states(ghost, 1.0 + TIMEOUT_S + 0.01)
    assert ghost.sources(1.0 + TIMEOUT_S + 0.01) == {'left': REAL, 'right': REAL}
    assert_arm(got, real_arm('left'))
    assert_arm(got, real_arm('right'))


def test_joints_no_puppet_drives_take_the_real_robots_values_and_unknown_names_are_dropped():
    ghost = make()
    ghost.on_puppet(1.0, 'R', PUPPET_NAMES, POSE_R)
    got = states(ghost, 1.0)
    assert got['ghost/head_pan'] == 0.3 and got['ghost/r_gripper_l_finger_joint'] == 0.01
    assert 'ghost/head_nod' not in got and 'ghost/torso_t0' not in got
    assert all(name.startswith('ghost/') for name in got)


def test_nothing_is_published_before_anything_is_known():
    limits = {s: baxter_description.arm_limits(s) for s in ('left', 'right')}
    ghost = GhostPose(limits, list(LIMITS), TIMEOUT_S, 'ghost/')
    assert ghost.joint_states(5.0) == ([], [])
    ghost.on_puppet(5.0, 'L', PUPPET_NAMES, POSE_L)  # a puppet alone: its arms only
    assert set(states(ghost, 5.0)) == set(expected('left', POSE_L, False)) | set(
        expected('right', POSE_L, True))


def test_a_non_finite_angle_keeps_that_joints_last_angle_with_a_warning():
    ghost = make()
    ghost.on_puppet(1.0, 'R', PUPPET_NAMES, POSE_R)
    moved = [a + 0.1 for a in POSE_R]
    moved[3] = math.nan
    assert 'joint 3' in ghost.on_puppet(1.1, 'R', PUPPET_NAMES, moved)
    want = [a + 0.1 for a in POSE_R]
    want[3] = POSE_R[3]
    assert_arm(states(ghost, 1.1), expected('right', want, mirrored=False))


def test_a_puppet_with_a_joint_never_valid_does_not_move_the_ghost():
    ghost = make()
    ghost.on_puppet(1.0, 'R', PUPPET_NAMES, POSE_R[:6] + [math.nan])
    assert ghost.sources(1.0) == {'left': REAL, 'right': REAL}
    assert_arm(states(ghost, 1.0), real_arm('right'))


@pytest.mark.parametrize('names, positions', [
    (['a%d' % j for j in range(7)], POSE_L),
    (PUPPET_NAMES[:6], POSE_L[:6]),
    (PUPPET_NAMES, POSE_L[:5]),
])
def test_puppet_states_with_wrong_names_are_refused_and_change_nothing(names, positions):
    ghost = make()
    ghost.on_puppet(1.0, 'R', PUPPET_NAMES, POSE_R)
    before = states(ghost, 1.1)
    assert 'ignored' in ghost.on_puppet(1.1, 'R', names, positions)
    assert states(ghost, 1.1) == before
    assert ghost.sources(1.0 + TIMEOUT_S + 0.01)['right'] == REAL  # no freshness either


def test_garbage_real_states_are_refused_and_non_finite_values_keep_the_last():
    ghost = make()
    before = states(ghost, 0.0)
    assert 'ignored' in ghost.on_robot(['head_pan'], [])
    assert 'head_pan' in ghost.on_robot(['head_pan', 'left_s0'], [math.nan, 0.9])
    got = states(ghost, 0.0)
    assert got['ghost/head_pan'] == before['ghost/head_pan'] and got['ghost/left_s0'] == 0.9


def test_an_arm_both_puppets_claim_for_a_moment_shows_the_puppet_on_its_side():
    ghost = make()
    ghost.on_puppet(1.0, 'R', PUPPET_NAMES, POSE_R)
    ghost.on_puppet(1.0, 'L', PUPPET_NAMES, POSE_L)
    ghost.on_teleop('R', follow_left=True, follow_right=True)
    ghost.on_teleop('L', follow_left=True, follow_right=True)
    assert ghost.sources(1.0) == {'left': 'L', 'right': 'R'}


def test_a_calibration_target_is_shown_like_a_puppet_and_dropped_when_it_stops():
    ghost = make()
    real = states(ghost, 0.0)
    names = ['right_%s' % s for s in SUFFIXES]
    # Baxter's names in any order, with an extra joint: mapped by name.
    order = [6, 0, 5, 1, 4, 2, 3]
    assert ghost.on_target(1.0, 'R', [names[k] for k in order] + ['head_pan'],
                           [POSE_R[k] for k in order] + [9.0]) == ''
    shown = states(ghost, 1.2)
    for name, angle in {**expected('right', POSE_R, False),
                        **expected('left', POSE_R, True)}.items():
        assert shown[name] == pytest.approx(angle, abs=1e-12)
    assert shown['ghost/head_pan'] == real['ghost/head_pan']
    assert states(ghost, 1.0 + TIMEOUT_S + 0.01) == real  # no target repeated: the real robot


def test_a_target_without_its_arm_s_names_is_refused():
    ghost = make()
    left_names = ['left_%s' % s for s in SUFFIXES]
    assert 'ignored' in ghost.on_target(1.0, 'R', left_names, POSE_L)  # R needs right_*
    assert 'ignored' in ghost.on_target(1.0, 'L', left_names, POSE_L[:6])
    assert ghost.sources(1.0) == {'left': REAL, 'right': REAL}


def test_the_refusal_of_a_garbage_target_stays_one_short_line():
    # Garbage on the target topic (a 10^5-character name) once made a 100 kB log line.
    warning = make().on_target(1.0, 'L', ['', 'x' * 100000], [0.0, 0.0])
    assert 'ignored' in warning and len(warning) < 300
