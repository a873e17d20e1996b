"""assist_follow: the newest assist target per arm, when it engages, its plan, hold and detail."""
import math

import pytest

from robopuppet.arm import assist_follow
from robopuppet.arm.assist_follow import ASSIST_TIMEOUT_S, AssistFollow, Plan, who_drives

TARGET = [0.1, -0.2, 0.3, 0.4, -0.5, 0.6, -0.7]


def test_a_target_engages_only_while_fresh_and_never_on_the_own_arm():
    assist = AssistFollow('right')
    assert not assist.engage('left', 0.0)   # none yet
    assert assist.on_target(0.0, 'left', TARGET, False, True, 'assist holding: x') == ''
    assert assist.engage('left', 0.1)       # it says hold: engaged, holding
    assert assist.plan('left', 0.1).positions is None
    assist.release('left')
    assert assist.on_target(0.0, 'left', TARGET, False, False, '') == ''
    assert not assist.engage('left', ASSIST_TIMEOUT_S + 0.001)   # too old
    assert assist.engage('left', ASSIST_TIMEOUT_S)
    assert assist.assisted == {'left': True, 'right': False}
    assert assist.on_target(0.0, 'right', TARGET, False, False, '') != ''
    assert not assist.engage('right', 0.0) and assist.refused == 1


@pytest.mark.parametrize('side, positions', [
    ('left', TARGET[:6]), ('left', TARGET + [0.0]), ('left', TARGET[:6] + [math.nan]),
    ('left', [math.inf] * 7), ('up', TARGET), ('right', TARGET)])
def test_refused_targets_say_why_and_leave_the_last_good_one(side, positions):
    assist = AssistFollow('right')
    assist.on_target(0.0, 'left', TARGET, True, False, '')
    assert assist_follow.refusal('right', side, positions)
    assert assist.on_target(0.05, side, positions, False, True, 'x') != ''
    assert assist.engage('left', 0.1)
    assert assist.plan('left', 0.1) == Plan(TARGET, False, True)


def test_the_plan_holds_on_a_hold_or_old_target_says_why_and_grips_only_on_changes():
    assist = AssistFollow('left')
    assist.on_target(0.0, 'right', TARGET, True, False, '')
    assert assist.engage('right', 0.0)
    assert assist.plan('right', 0.01) == Plan(TARGET, False, True)   # grip on engaging
    assert assist.plan('right', 0.02) == Plan(TARGET, False, None)
    assert assist.gripper_closed('right') and not assist.gripper_closed('left')
    assert assist.plan('right', 0.21) == Plan(None, True, None)   # no target for 0.2 s
    assert assist.hold_detail(0.21) == 'assist holding: no prediction for 0.2 s'
    assert assist.plan('right', 0.22) == Plan(None, False, None)
    assist.on_target(0.3, 'right', TARGET, False, True, 'assist holding: unfamiliar motion')
    assert assist.plan('right', 0.3) == Plan(None, False, None)
    assert assist.hold_detail(0.3) == 'assist holding: unfamiliar motion'   # said once
    assist.on_target(0.31, 'right', TARGET, False, True, 'the leader moved too fast')
    assert assist.hold_detail(0.31) == 'assist holding: the leader moved too fast'
    assist.on_target(0.31, 'right', TARGET, False, True, 'assist stopped: press Start assist')
    assert assist.hold_detail(0.31) == 'assist stopped: press Start assist'
    assist.on_target(0.32, 'right', TARGET, False, False, '')
    assert assist.plan('right', 0.32) == Plan(TARGET, True, False)   # moves again, opens
    assert assist.hold_detail(0.32) == ''
    assist.release_all()
    assert not any(assist.assisted.values()) and not assist.gripper_closed('right')


@pytest.mark.parametrize('followers, assisted, text', [
    ([], [], 'no Baxter arm follows; press 2 or 3 to follow'),
    (['right'], [], 'Baxter follows with its right arm'),
    (['left', 'right'], [], 'Baxter follows with its left and right arms'),
    ([], ['left'], "the assist drives Baxter's left arm"),
    (['right'], ['left'], 'Baxter follows with its right arm; the assist drives its left arm')])
def test_the_detail_names_who_drives_which_arm(followers, assisted, text):
    assert who_drives(followers, assisted) == text
