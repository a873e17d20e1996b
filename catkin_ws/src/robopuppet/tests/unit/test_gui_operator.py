"""pytest-qt tests of the operator's day: values from the robot room greyed with their age once
not current, every settings problem beside its field, the camera beside the status (the arm's
own camera first), and a virtual button click held long enough for the firmware to see it."""
import os
import time

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402
from PyQt5 import QtCore, QtGui  # noqa: E402

from robopuppet.gui import freshness, joint_tab, look, main_tab, sim_panel, state  # noqa: E402
from robopuppet.gui.window import Window  # noqa: E402
from test_camera_pane import CameraClientDouble, jpeg_of  # noqa: E402
from test_gui_widgets import (FakeClient, FakeSim, PUPPET_RAD, background, column,  # noqa: E402
                              feel_teleop, fill, read_tab, robot_joints)

GREY = QtGui.QColor(look.GREY).name()
STALE_TEXT = QtGui.QColor(freshness.STALE_TEXT_COLOUR).name()


@pytest.fixture
def client():
    return FakeClient()


@pytest.fixture
def window(qtbot, client):
    win = Window(client, debug_mode=False)
    qtbot.addWidget(win)
    win.show()
    return win


def calibrating(received_s):
    return state.Teleop('calibrating', False, True, 'limp', 0.1, 'joint 0 Uncalibrated', '',
                        'patient head', received_s)


# ---- item 3: nothing from the robot room shown as live once it is not ------------------------
def test_the_teleop_state_greys_out_with_its_age_once_the_robot_room_is_silent(window, client):
    tab = window.main_tab
    client.state.on_teleop(calibrating(99.9))
    window.frame()
    assert look.AMBER in tab.teleop_label.styleSheet()
    assert 'NOT CURRENT' not in tab.teleop_label.text()
    assert tab.teleop_age_label.text() == 'arm_R: 100 ms ago'
    assert "keep-out zone 'patient head'" in tab.tracking_label.text()
    client.time_s = 115.0  # "No link to the robot room: nothing heard for 15 s"
    window.frame()
    assert look.AMBER not in tab.teleop_label.styleSheet()
    assert look.GREY in tab.teleop_label.styleSheet()
    assert tab.teleop_label.text() == 'state: calibrating   (opmode limp)   NOT CURRENT'
    assert tab.teleop_age_label.text() == \
        'NOT CURRENT: arm_R last heard 15 s ago'
    for label in (tab.follow_label, tab.detail_label):
        assert freshness.STALE_TEXT_COLOUR in label.styleSheet()
    # the zone line came from the same report: not shown as current either
    assert tab.tracking_label.text().startswith('NOT CURRENT: no report from the arm '
                                                'controller for 15 s')
    assert look.GREY in tab.tracking_label.styleSheet()
    client.state.on_teleop(calibrating(115.0))  # the robot room is back
    window.frame()
    assert look.AMBER in tab.teleop_label.styleSheet()
    assert freshness.STALE_TEXT_COLOUR not in tab.follow_label.styleSheet()


def test_baxters_last_pose_is_greyed_with_its_age_and_no_error(window, client):
    arm, table = client.state, window.main_tab.joint_table
    for joint, angle in enumerate(PUPPET_RAD):
        arm.on_angle(joint, angle, 99.9)
    robot_joints(arm, 99.9)
    arm.on_teleop(feel_teleop(True, False, received_s=99.9))
    window.frame()
    live = column(table, main_tab.BAXTER_COLUMN)
    assert '—' not in live and table.item(0, main_tab.BAXTER_COLUMN).foreground().color().name() \
        != STALE_TEXT
    assert window.main_tab.baxter_age_label.text() == \
        "Baxter's pose: 100 ms ago"
    client.time_s = 103.0
    arm.on_teleop(feel_teleop(True, False, received_s=103.0))  # arm_X still reports
    window.frame()
    assert column(table, main_tab.BAXTER_COLUMN) == live  # the last pose, greyed
    for row in range(table.rowCount()):
        cell = table.item(row, main_tab.BAXTER_COLUMN)
        assert cell.foreground().color().name() == STALE_TEXT and background(cell) == GREY
    assert set(column(table, main_tab.ERROR_COLUMN)) == {'—'}  # never against an old pose
    assert window.main_tab.baxter_age_label.text() == \
        "NOT CURRENT: Baxter's pose last heard 3.1 s ago"
    assert 'for 3 s' in window.main_tab.tracking_label.text()


def test_the_link_box_shows_the_age_of_link_state_and_greys_its_figures(window, client):
    box = window.main_tab.link_box
    client.state.on_robot_link(state.RobotLink(0.02, 0.05, 0.35, True, 0.0, 0, 'none', '',
                                               99.8))
    window.frame()
    assert box.age_label.text() == 'link_state: 200 ms ago'
    assert box.rtt_label.styleSheet() == ''
    client.time_s = 115.0
    window.frame()
    assert box.age_label.text() == 'NOT CURRENT: link_state last heard 15 s ago'
    assert freshness.STALE_TEXT_COLOUR in box.rtt_label.styleSheet()


# ---- item 8: every settings problem at once, whole, at its field -----------------------------
def test_every_settings_problem_shows_at_once_beside_its_field(qtbot, client):
    tab = read_tab(qtbot, client, 4)
    tab.resize(1280, 760)
    tab.show()
    qtbot.waitExposed(tab)
    fill(tab, pid_kp='fast', angle_min='1', angle_max='0.5', sign_angle='2', voltage_max='9')
    qtbot.mouseClick(tab.set_button, QtCore.Qt.LeftButton)
    assert client.requests == []
    expected = {'pid_kp': "pid_kp = 'fast': not a number",
                'sign_angle': 'sign_angle = 2.0: a sign must be +1 or -1',
                'angle_min': 'angle_min = 1.0: above angle_max = 0.5',
                'angle_max': 'angle_min = 1.0: above angle_max = 0.5'}
    for name, field in tab.fields.items():
        label = tab.field_problems[name]
        if name in expected or name == 'voltage_max':
            assert field.styleSheet() == joint_tab.FIELD_ERROR_STYLE, name
            assert label.isVisible() and label.text() in field.toolTip()
        else:
            assert field.styleSheet() == '' and not label.isVisible(), name
    for name, text in expected.items():
        assert tab.field_problems[name].text() == text
    assert 'outside its bound' in tab.field_problems['voltage_max'].text()
    assert '4 problems' in tab.message.text()
    qtbot.wait(50)  # laid out
    for label in [tab.message] + [tab.field_problems[name] for name in expected]:
        # whole: wrapped to its width and as tall as its text needs, inside the tab
        assert label.height() >= label.heightForWidth(label.width()), label.text()
        bottom = label.mapTo(tab, QtCore.QPoint(0, label.height())).y()
        assert bottom <= tab.height(), label.text()
    qtbot.keyClicks(tab.fields['pid_kp'], '1')  # editing a field clears its mark
    assert tab.fields['pid_kp'].styleSheet() == '' and not tab.field_problems['pid_kp'].isVisible()
    fill(tab)
    tab.fields['pid_kp'].setText('0.5')
    qtbot.mouseClick(tab.set_button, QtCore.Qt.LeftButton)
    qtbot.waitUntil(lambda: not tab.busy(), timeout=5000)
    assert all(field.styleSheet() == '' for field in tab.fields.values())


# ---- item 10: the camera beside the status, the arm's own first ------------------------------
CAMERA_TOPICS = [('/cameras/%s/image/compressed' % name, 'sensor_msgs/CompressedImage')
                 for name in ('head_camera', 'left_hand_camera', 'right_hand_camera',
                              'room_camera')]


def operator_window(qtbot, side, cameras):
    client = FakeClient()
    client.side = side
    win = Window(client, debug_mode=False, cameras=cameras)
    qtbot.addWidget(win)
    win.show()
    qtbot.waitExposed(win)
    qtbot.waitUntil(lambda: cameras.camera_list() is not None)
    win.frame()
    return win, client


@pytest.mark.parametrize('side, own', [('R', 'right_hand_camera'), ('L', 'left_hand_camera')])
def test_the_camera_shows_beside_the_status_on_the_arms_own_camera(qtbot, side, own):
    cameras = CameraClientDouble(CAMERA_TOPICS)
    win, _ = operator_window(qtbot, side, cameras)
    pane, tab = win.camera_pane, win.main_tab
    assert win.tabs.currentWidget() is win.main_tab
    assert pane.isVisible() and tab.isVisible()  # one view: both at once
    for status in (tab.teleop_label, tab.link_box, tab.joint_table):  # the camera to the right
        assert pane.mapTo(win, QtCore.QPoint(0, 0)).x() >= status.mapTo(win, QtCore.QPoint(
            status.width(), 0)).x()
    assert pane.width() >= 380 and pane.view.height() >= 200  # at the default 1280x760
    assert cameras.active() == [own]
    cameras.publish(jpeg_of((0, 0, 255)))
    win.frame()
    assert pane.view.has_image() and tab.teleop_label.text() == 'no arm controller'


def test_the_camera_follows_the_driven_arm_until_the_operator_chooses(qtbot):
    cameras = CameraClientDouble(CAMERA_TOPICS)
    win, client = operator_window(qtbot, 'R', cameras)
    pane = win.camera_pane
    assert cameras.active() == ['right_hand_camera']
    client.state.on_teleop(feel_teleop(True, False, received_s=client.time_s))
    win.frame()  # puppet R drives Baxter's left arm (mirrored): its camera
    assert cameras.active() == ['left_hand_camera']
    pane.chooser.activated.emit(pane.chooser.findData('room_camera'))  # the nurse chooses
    client.state.on_teleop(feel_teleop(False, True, received_s=client.time_s))
    win.frame()
    assert cameras.active() == ['room_camera']
    win.tabs.setCurrentWidget(win.calibration_tab)  # the page is hidden: nothing subscribed
    assert cameras.active() == []
    win.tabs.setCurrentWidget(win.main_tab)
    win.frame()
    assert cameras.active() == ['room_camera']


# ---- item 11: a 0 ms click on a virtual button is not lost -----------------------------------
class TimedSim(FakeSim):
    """A FakeSim that also records when each button and end-piece reading was sent."""

    def __init__(self):
        super().__init__()
        self.times = []

    def set_button(self, button):
        super().set_button(button)
        self.times.append((time.monotonic(), 'button', button))

    def set_grippers(self, readings):
        super().set_grippers(readings)
        self.times.append((time.monotonic(), 'end piece', readings[-1]))


def held_s(sim, kind):
    (pressed_s, _, _), (released_s, _, _) = [t for t in sim.times if t[1] == kind]
    return released_s - pressed_s


def test_an_instant_click_is_held_for_two_state_periods(qtbot):
    sim = TimedSim()
    panel = sim_panel.SimPanel(sim)
    qtbot.addWidget(panel)
    qtbot.mouseClick(panel.user_buttons[2], QtCore.Qt.LeftButton)  # press and release, 0 ms
    assert sim.buttons == [3]  # still held: the firmware has not sampled it yet
    qtbot.mouseClick(panel.end_piece_button, QtCore.Qt.LeftButton)
    assert [g[-1] for g in sim.grippers] == [0.0]
    qtbot.waitUntil(lambda: sim.buttons == [3, 0] and len(sim.grippers) == 2, timeout=2000)
    assert sim.grippers[-1][-1] == 1.0
    assert sim_panel.MIN_PRESS_S >= 2.0 / 10.0  # two periods of the firmware's 10 Hz
    for kind in ('button', 'end piece'):
        assert sim_panel.MIN_PRESS_S - 0.01 <= held_s(sim, kind) < sim_panel.MIN_PRESS_S + 0.5


def test_a_long_press_ends_at_release_and_a_new_press_is_not_cut_short(qtbot):
    sim = TimedSim()
    panel = sim_panel.SimPanel(sim)
    qtbot.addWidget(panel)
    qtbot.mousePress(panel.user_buttons[0], QtCore.Qt.LeftButton)
    qtbot.wait(int(sim_panel.MIN_PRESS_S * 1000) + 50)
    qtbot.mouseRelease(panel.user_buttons[0], QtCore.Qt.LeftButton)
    assert sim.buttons == [1, 0]  # held long enough already: released at once
    qtbot.mouseClick(panel.user_buttons[1], QtCore.Qt.LeftButton)
    qtbot.mousePress(panel.user_buttons[2], QtCore.Qt.LeftButton)  # before 2's release is due
    qtbot.wait(int(sim_panel.MIN_PRESS_S * 1000) + 100)
    assert sim.buttons == [1, 0, 2, 3]  # 3 held down: 2's late release does not lift it
    qtbot.mouseRelease(panel.user_buttons[2], QtCore.Qt.LeftButton)
    assert sim.buttons[-1] == 0
