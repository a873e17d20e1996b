"""The calibration steps (procedure) and the GUI wizard on a fake puppet whose firmware reports
sign_angle * wrap(raw - sign_angle * home_angle) with the settings stored in a fake config_X."""
import math
import os
import threading

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402

from robopuppet import interface, settings  # noqa: E402
from robopuppet.calibration import procedure  # noqa: E402
from robopuppet.config import config_store, settings_keeper  # noqa: E402
from robopuppet.gui import state  # noqa: E402
from robopuppet.gui.calibration_tab import CalibrationTab  # noqa: E402
from robopuppet.gui.puppet_client import SetAnswer  # noqa: E402

# How the fake puppet's encoders are mounted: raw = sign * q + offset (offsets near +-pi too).
TRUE_SIGNS = (1.0, -1.0, 1.0, 1.0, -1.0, 1.0, 1.0)
TRUE_OFFSETS = (0.3, -3.13, 3.13, -1.0, 2.0, 0.0, -0.7)
WIDE = {'angle_min': -math.pi, 'angle_max': math.pi}


def report(q, joint, cfg):
    """The firmware's reported angle of joint at Baxter angle q with settings cfg (the oracle)."""
    raw = TRUE_SIGNS[joint] * q + TRUE_OFFSETS[joint]
    x = raw - cfg['sign_angle'] * cfg['home_angle']
    return cfg['sign_angle'] * math.atan2(math.sin(x), math.cos(x))


class FakeArm:
    """A fake client: ArmState readings from a hand pose; set_arm_config as config_X (all joints
    or none); requests counts its calls."""

    side = 'R'

    def __init__(self):
        self.state = state.ArmState()
        self.stored = config_store.defaults()
        for joint in settings.JOINTS:
            self.stored[joint].update(WIDE)
        self.refuse_joint = None
        self.requests = 0
        self.targets = []  # poses published as the calibration target
        self._lock = threading.RLock()

    def publish_target(self, pose):
        self.targets.append(pose)

    def now(self):
        return 0.0

    def stored_settings(self):
        with self._lock:
            return {j: dict(v) for j, v in self.stored.items()}

    def set_arm_config(self, values):
        with self._lock:
            self.requests += 1
            if self.refuse_joint in values:
                return SetAnswer(False, 'joint %d refused for the test' % self.refuse_joint,
                                 self.stored_settings())
            self.stored = settings_keeper.check_arm_request(
                self.stored, [(j, list(v), list(v.values())) for j, v in values.items()])
            return SetAnswer(True, '', self.stored_settings())

    def pose(self, angles_rad, status=interface.WORKING, end_piece=1.0):
        stored = self.stored_settings()
        for joint, q in enumerate(angles_rad):
            self.state.on_status(joint, status if joint in settings.QUAD_JOINTS
                                 else interface.WORKING)
            self.state.on_angle(joint, report(q, joint, stored[joint]), 0.0)
        self.state.on_gripper(interface.END_PIECE_GRIPPER, end_piece)


@pytest.fixture
def arm():
    return FakeArm()


@pytest.fixture
def tab(qtbot, arm):
    widget = CalibrationTab(arm)
    qtbot.addWidget(widget)
    return widget


def frame(tab, arm):
    tab.refresh(arm.state.snapshot(), 0.0)


def press_end_piece(tab, arm, pose):
    for reading in (1.0, 0.0, 1.0):
        arm.pose(pose, end_piece=reading)
        frame(tab, arm)


def capture_all(tab, arm, qtbot):
    arm.pose(procedure.POSES[0].angles_rad, status=interface.UNCALIBRATED)
    frame(tab, arm)
    tab.start()
    assert tab.step == 'encoders' and '[0, 2, 4, 6]' in tab.instruction.text()
    assert not tab.buttons['Capture'].isEnabled()
    for pose in procedure.POSES:
        arm.pose(pose.angles_rad)
        frame(tab, arm)
        assert tab.figure.targets_rad == list(pose.angles_rad)
        press_end_piece(tab, arm, pose.angles_rad)
    assert tab.step == 'review'


def test_the_wizard_solves_applies_and_undoes(tab, arm, qtbot):
    before = arm.stored_settings()
    capture_all(tab, arm, qtbot)
    assert tab.buttons['Apply'].isEnabled()
    assert tab.table.item(1, 4).text() == '+1'
    assert tab.table.item(1, 5).text() == '-1'  # old and new side by side
    assert arm.stored_settings() == before  # nothing written before Apply
    tab.apply()
    qtbot.waitUntil(lambda: not tab._task.busy(), timeout=5000)
    assert 'stored the new values' in tab.message.text()
    assert arm.requests == 1, 'every joint in one all-or-none request'
    after = arm.stored_settings()
    for pose in procedure.POSES:
        for joint, q in enumerate(pose.angles_rad):
            assert abs(report(q, joint, after[joint]) - q) < 1e-3
    assert [after[j]['sign_angle'] for j in settings.JOINTS] == list(TRUE_SIGNS)
    tab.undo()
    qtbot.waitUntil(lambda: not tab._task.busy(), timeout=5000)
    assert arm.stored_settings() == before
    assert not tab.buttons['Undo'].isEnabled()


def test_a_refused_joint_refuses_the_whole_calibration_and_leaves_nothing_to_undo(tab, arm,
                                                                                   qtbot):
    before = arm.stored_settings()
    capture_all(tab, arm, qtbot)
    arm.refuse_joint = 3
    tab.apply()
    qtbot.waitUntil(lambda: not tab._task.busy(), timeout=5000)
    assert 'FAILED: refused: joint 3 refused' in tab.message.text()
    assert 'every joint keeps what it had' in tab.message.text()
    assert arm.stored_settings() == before
    assert tab.undo_values == {} and not tab.buttons['Undo'].isEnabled()
    assert tab.buttons['Apply'].isEnabled(), 'Apply may be tried again'


def teleop(follow_right, received_s=0.0):
    return state.Teleop(interface.FOLLOWING if follow_right else interface.READY, False,
                        follow_right, interface.LIMP, 0.1, '', '', '', received_s)


def test_apply_is_disabled_while_the_arm_follows_and_says_why(tab, arm, qtbot):
    """A new home or sign would move a following Baxter arm (config_X refuses it then too)."""
    before = arm.stored_settings()
    capture_all(tab, arm, qtbot)
    arm.state.on_teleop(teleop(True))
    frame(tab, arm)
    apply = tab.buttons['Apply']
    assert not apply.isEnabled()
    assert apply.toolTip() == ("Baxter's right arm follows this puppet: stop following first: "
                               'press 3')
    tab.apply()   # not through the button: refused in the window, nothing sent
    assert 'not applied' in tab.message.text() and 'press 3' in tab.message.text()
    assert arm.stored_settings() == before
    tab.refresh(arm.state.snapshot(), 2.5)   # a teleop_state 2.5 s old: arm_X stops itself
    assert apply.isEnabled() and apply.toolTip() == ''
    arm.state.on_teleop(teleop(False, received_s=2.5))
    frame(tab, arm)
    assert apply.isEnabled()


def test_undo_of_home_and_sign_is_disabled_while_the_arm_follows(tab, arm, qtbot):
    capture_all(tab, arm, qtbot)
    tab.apply()
    qtbot.waitUntil(lambda: not tab._task.busy(), timeout=5000)
    assert tab.buttons['Undo'].isEnabled()
    arm.state.on_teleop(teleop(True))
    frame(tab, arm)
    assert not tab.buttons['Undo'].isEnabled()
    assert 'press 3' in tab.buttons['Undo'].toolTip()


def test_a_refusal_because_the_arm_follows_is_shown(tab, arm, qtbot):
    capture_all(tab, arm, qtbot)
    why = ("joint 0 home_angle and sign_angle change what the puppet's angles mean, and Baxter's "
           'right arm follows this puppet: stop following first: press 3')
    arm.set_arm_config = lambda values: SetAnswer(False, why, {})
    tab.apply()   # arm_X's teleop_state had not reached the window yet
    qtbot.waitUntil(lambda: not tab._task.busy(), timeout=5000)
    assert 'FAILED: refused: ' + why in tab.message.text()


def test_a_clamped_or_uncalibrated_reading_is_not_captured(tab, arm):
    arm.pose(procedure.POSES[0].angles_rad)
    frame(tab, arm)
    tab.start()
    for joint in settings.JOINTS:
        arm.stored[joint]['angle_max'] = 0.3  # joint 0 reads 0.3 (its offset): clamped
    tab.capture()
    assert tab.session.raws == [] and 'joint 0 reads 0.300 rad, at its limit' in \
        tab.message.text()
    for joint in settings.JOINTS:
        arm.stored[joint].update(WIDE)
    arm.state.on_status(2, interface.UNCALIBRATED)
    frame(tab, arm)
    tab.capture()
    assert tab.session.raws == [] and 'joint 2 is Uncalibrated' in tab.message.text()


def test_an_end_piece_held_at_the_start_does_not_capture(tab, arm):
    arm.pose(procedure.POSES[0].angles_rad, end_piece=0.0)
    frame(tab, arm)
    tab.start()
    frame(tab, arm)
    assert tab.session.raws == []
    press_end_piece(tab, arm, procedure.POSES[0].angles_rad)
    assert len(tab.session.raws) == 1


def test_a_wrong_pose_is_flagged_and_apply_is_refused(tab, arm, qtbot):
    arm.pose(procedure.POSES[0].angles_rad)
    frame(tab, arm)
    tab.start()
    for k, pose in enumerate(procedure.POSES):
        angles = list(pose.angles_rad)
        if k == 1:
            angles[5] += 0.4  # the operator got joint 5 wrong in pose A
        press_end_piece(tab, arm, angles)
    assert tab.step == 'review' and not tab.buttons['Apply'].isEnabled()
    assert 'flagged' in tab.instruction.text() and 'pose 2' in tab.table.item(5, 7).text()
    tab.retake()
    assert tab.step == 'pose'
    press_end_piece(tab, arm, procedure.POSES[2].angles_rad)
    assert tab.step == 'review'


def test_the_check_names_a_joint_that_moves_the_wrong_way(tab, arm):
    for joint in settings.JOINTS:  # calibrated: the puppet reports Baxter's angles
        arm.stored[joint].update(sign_angle=TRUE_SIGNS[joint],
                                 home_angle=TRUE_SIGNS[joint] * TRUE_OFFSETS[joint])
    tab.start_check()
    angles = [0.0] * settings.NUM_JOINTS
    for joint in settings.JOINTS:
        assert str(joint) in tab.instruction.text()
        for step in (0.0, 0.1, 0.25):
            angles[joint] = -step if joint == 4 else step
            arm.pose(angles)
            frame(tab, arm)
    assert tab.check.wrong() == [4]
    assert '[4]' in tab.message.text() and 'WRONG' in tab.table.item(4, 7).text()


def test_apply_changes_sends_every_joint_in_one_request_and_stores_all_or_none():
    calls = []

    def set_arm_config(values):
        calls.append(values)
        if len(calls) == 2:
            raise RuntimeError('no service')
        return SetAnswer(len(calls) == 1, '' if len(calls) == 1 else 'joint 2 bad', {})

    values = {j: {'sign_angle': 1.0} for j in (3, 0, 2, 1)}
    assert procedure.apply_changes(set_arm_config, values) == procedure.Applied([0, 1, 2, 3], '')
    assert calls == [{j: {'sign_angle': 1.0} for j in (0, 1, 2, 3)}]
    assert procedure.apply_changes(set_arm_config, values) == procedure.Applied([], 'no service')
    assert procedure.apply_changes(set_arm_config, values) == procedure.Applied(
        [], 'refused: joint 2 bad')
    assert len(calls) == 3


def test_end_piece_press_has_hysteresis():
    press = procedure.EndPiecePress()
    readings = (0.0, 1.0, 0.5, 0.2, 0.1, 0.5, 0.2, 0.8, 0.25, math.nan)
    assert [press.update(r) for r in readings] == [False, False, False, True, False, False,
                                                  False, False, True, False]


def test_the_awaited_pose_is_published_as_the_target_and_nothing_otherwise(tab, arm):
    arm.pose(procedure.POSES[0].angles_rad)
    tab._tick()
    assert arm.targets == []  # no calibration running
    tab.start()
    for pose in procedure.POSES:
        arm.pose(pose.angles_rad)
        frame(tab, arm)
        tab._tick()
        assert arm.targets[-1] == pose
        press_end_piece(tab, arm, pose.angles_rad)
    assert tab.step == 'review'
    published = len(arm.targets)
    tab._tick()
    assert len(arm.targets) == published
    assert procedure.target_state('R', procedure.POSES[1]) == (
        ['right_s0', 'right_s1', 'right_e0', 'right_e1', 'right_w0', 'right_w1', 'right_w2'],
        [0.5, -0.5, 0.5, 0.5, 0.5, 0.5, 0.5])
    assert procedure.target_state('L', procedure.POSES[0])[0][0] == 'left_s0'
