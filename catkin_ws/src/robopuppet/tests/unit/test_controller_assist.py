"""arm_X's controller and the assist: the targets it refuses (as the node's assist_target topic
feeds them) and the report that names the assisted arm."""
import math

import pytest

from robopuppet import interface
from robopuppet.arm import baxter_upkeep
from test_controller import Rig, report_in

TARGET = [0.3, -0.4, -0.2, 0.9, 0.1, 1.0, -0.2]


def target(rig, side='left', positions=TARGET, closed=False, hold=False, detail=''):
    return rig.core.on_assist_target(rig.t, side, positions, closed, hold, detail)


@pytest.mark.parametrize('side, positions, why', [
    ('right', TARGET, "assist target for Baxter's right arm refused: this puppet drives that "
                      'arm itself'),
    ('torso', TARGET, "assist target for an unknown arm 'torso' refused (left or right)"),
    ('', TARGET, "assist target for an unknown arm '' refused (left or right)"),
    ('left', TARGET[:6], 'assist target refused: its positions are not 7 finite angles'),
    ('left', TARGET[:6] + [math.nan], 'assist target refused: its positions are not 7 finite'),
    ('left', TARGET + [0.0], 'assist target refused: its positions are not 7 finite angles'),
    ('left', TARGET[:6] + [math.inf], 'assist target refused: its positions are not 7 finite'),
])
def test_a_target_it_cannot_use_is_refused_counted_and_never_engages(side, positions, why):
    rig = Rig()
    rig.step()
    assert target(rig, side, positions).startswith(why)
    rig.core.on_button(interface.BUTTON_LEFT)
    out = rig.step()   # button 2 mirrors the puppet as without the assist
    assert rig.core.teleop.following['left'] and not rig.core.teleop.assist.assisted['left']
    assert rig.core.teleop.assist.refused == 1
    rig.step(0.5)
    report = report_in(rig.step()) or report_in(out)
    assert ('refused_assist_targets', '1') in report.values


def test_the_report_names_the_assisted_arm_apart_from_the_following_ones():
    rig = Rig()
    rig.step()
    assert target(rig) == ''
    rig.core.on_button(interface.BUTTON_LEFT)
    report = report_in(rig.step())
    rig.core.on_button(0)
    assert report.changed and report.state == interface.FOLLOWING
    assert (report.follow_left, report.follow_right, report.assist_left, report.assist_right) \
        == (False, False, True, False)
    assert report.detail == "the assist drives Baxter's left arm"
    assert ('assist_left', 'True') in report.values
    assert target(rig) == ''
    rig.core.on_button(interface.BUTTON_RIGHT)
    report = report_in(rig.step())
    assert (report.follow_right, report.assist_left) == (True, True)
    assert report.detail == 'Baxter follows with its right arm; the assist drives its left arm'


def test_the_assist_grips_through_baxters_gripper_api_and_a_closed_one_is_not_calibrated():
    rig = Rig()
    rig.core.on_gripper_state(rig.t, 'left', 65539, True)
    rig.step()
    assert target(rig, closed=True) == ''
    rig.core.on_button(interface.BUTTON_LEFT)
    grips = [a for a in rig.step() if isinstance(a, baxter_upkeep.GripperCommand)]
    assert [(g.side, g.id, g.command, g.args) for g in grips] == [
        ('left', 65539, 'go', '{"position": 0.0}')]
    assert rig.core.on_gripper_state(rig.t, 'left', 65539, False) == []
