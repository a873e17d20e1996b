"""The calibration tab's motor check (gui.motor_step) and "Pose the virtual puppet", on the fake
puppet of test_calibration_tab: results in a table (joint, result) with failures red, what
the operator must do before and after (the simulated puppet's "let go of the puppet"), and the
pose button sending the pose awaited to the simulated hand."""
import os

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402

from robopuppet import settings  # noqa: E402
from robopuppet.calibration import motor_check, procedure  # noqa: E402
from robopuppet.gui.calibration_tab import CalibrationTab  # noqa: E402
from robopuppet.gui.look import GREEN, RED  # noqa: E402
from test_calibration_tab import FakeArm, frame  # noqa: E402

SHOTS = os.environ.get('GUI_SHOTS', '')  # a folder: save screenshots there


class MotorArm(FakeArm):
    """FakeArm with a clock, opmodes and setpoints; joints in `moves` follow their setpoint."""

    def __init__(self, moves=()):
        super().__init__()
        self.t, self.moves, self.opmodes = 0.0, set(moves), []
        for joint in settings.JOINTS:
            self.state.on_angle(joint, 0.1, 0.0)

    def now(self):
        return self.t

    def set_opmode(self, opmode):
        self.opmodes.append(opmode)

    def set_setpoint(self, joint, angle_rad):
        if joint in self.moves:
            self.state.on_angle(joint, angle_rad, self.t)


class FakeSim:
    """A SimPuppetClient double: the hand messages it was asked to publish."""

    def __init__(self):
        self.hands = []

    def set_hand(self, angles_rad):
        self.hands.append(list(angles_rad))


def run_check(tab, arm, qtbot):
    tab.buttons['Motors'].click()
    assert tab.step == 'motors'
    while tab.step == 'motors':
        qtbot.waitUntil(lambda: not tab._task.busy(), timeout=5000)
        arm.t += 0.1
        tab._tick()
        assert arm.t < 100.0
    qtbot.waitUntil(lambda: not tab._task.busy(), timeout=5000)


def colour(item):
    return item.background().color().name() if item.background().style() else None


@pytest.mark.parametrize('sim', [True, False])
def test_the_results_are_a_table_with_failures_red_and_say_what_to_do(qtbot, sim):
    arm = MotorArm(moves={0, 1})
    tab = CalibrationTab(arm, sim=FakeSim() if sim else None)
    qtbot.addWidget(tab)
    tab.resize(1000, 640)
    tab.show()
    tab.buttons['Motors'].click()
    before = tab.instruction.text()
    assert 'joint 0' in before
    if sim:
        assert 'press "let go of the puppet"' in before
    else:
        assert 'let go of the puppet arm' in before and 'let go of the puppet"' not in before
    tab.stop_motors()
    qtbot.waitUntil(lambda: tab.step == 'idle', timeout=5000)
    run_check(tab, arm, qtbot)
    results = tab.motors.results
    assert results == {j: motor_check.RIGHT if j in (0, 1) else motor_check.UNKNOWN
                       for j in settings.JOINTS}
    table = tab._motor_step.table
    assert table.isVisible() and table.columnCount() == 2
    for joint in settings.JOINTS:
        assert table.item(joint, 0).text() == 'joint %d' % joint
        text, painted = table.item(joint, 1).text(), colour(table.item(joint, 1))
        if joint in (0, 1):
            assert text.startswith('right') and painted == GREEN
        else:
            assert text.startswith('did not move') and painted == RED
    message = tab.message.text()
    assert '{' not in message and 'did not move: joints 2, 3, 4, 5 and 6' in message
    assert RED in tab.message.styleSheet()
    after = tab.instruction.text()
    assert 'Joints 2, 3, 4, 5 and 6 did not move' in after
    if sim:
        assert 'Press "let go of the puppet"' in after and 'Virtual puppet panel' in after
    else:
        assert 'take hold of the puppet arm again' in after
    if SHOTS and sim:
        tab.grab().save(os.path.join(SHOTS, 'motor_check_results.png'))


def test_every_motor_right_is_green(qtbot):
    arm = MotorArm(moves=settings.JOINTS)
    tab = CalibrationTab(arm, sim=FakeSim())
    qtbot.addWidget(tab)
    run_check(tab, arm, qtbot)
    assert GREEN in tab.message.styleSheet() and 'right: joints 0, 1, 2' in tab.message.text()


def test_the_pose_button_sends_the_pose_awaited_to_the_simulated_hand(qtbot):
    arm, sim = FakeArm(), FakeSim()
    tab = CalibrationTab(arm, sim=sim)
    qtbot.addWidget(tab)
    tab.show()
    assert tab.pose_button.isVisible() and not tab.pose_button.isEnabled()
    arm.pose(procedure.POSES[0].angles_rad)
    frame(tab, arm)
    tab.start()
    frame(tab, arm)
    assert tab.step == 'pose' and tab.pose_button.isEnabled()
    posed = []
    tab.hand_posed.connect(posed.append)
    tab.pose_button.click()
    assert sim.hands == [list(procedure.POSES[0].angles_rad)] and posed == sim.hands
    tab.capture()
    tab.pose_button.click()
    assert sim.hands[-1] == list(procedure.POSES[1].angles_rad)
    assert procedure.POSES[1].name in tab.message.text()


def test_no_pose_button_without_the_simulated_puppet(qtbot):
    tab = CalibrationTab(FakeArm())
    qtbot.addWidget(tab)
    tab.show()
    assert not tab.pose_button.isVisible()
