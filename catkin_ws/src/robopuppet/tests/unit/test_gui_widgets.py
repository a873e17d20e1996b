"""pytest-qt tests of the GUI widgets, fed by injected ArmState data and a fake client."""
import math
import os
import threading

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402
from PyQt5 import QtCore, QtGui  # noqa: E402

from robopuppet import settings  # noqa: E402
from robopuppet.config import config_store  # noqa: E402
from robopuppet.gui import joint_tab, look, main_tab, settings_form, state  # noqa: E402
from robopuppet.gui.puppet_client import ConfigUnavailable, SetAnswer  # noqa: E402
from robopuppet.gui.window import Window  # noqa: E402
from robopuppet.puppet_sim.puppet_arm import REST_POSE_RAD  # noqa: E402


class FakeClient:
    """Stands in for PuppetClient: records what would be published; stores like config_X.

    set_config stores all or none by the config node's rules (config_store.check_request) and
    answers with what is stored, or with `refusal` when that is set.
    """

    side = 'R'

    def __init__(self):
        self.state = state.ArmState()
        self.time_s = 100.0
        self.published = []
        self.requests = []  # (joint, {name: value}) that set_config received
        self.config_up = True
        self.refusal = ''  # set_config refuses every request with this error when set
        self.answer = None  # a threading.Event that the config calls wait for (at most 5 s)
        self.stored = config_store.defaults()
        self._lock = threading.Lock()

    def now(self):
        return self.time_s

    def set_opmode(self, opmode):
        self.published.append(('opmode', opmode))

    def set_setpoint(self, joint, angle_rad):
        self.published.append(('setpoint', joint, angle_rad))

    def recording_status(self):
        return None  # no recorder: test_recording_box.py tests the Recording box

    def episodes_dir(self):
        return '/nonexistent/robopuppet/episodes'  # test_replay_box.py tests the replay control

    def stop_replay(self):
        self.published.append(('replay_stop',))

    def _reach(self):
        if self.answer is not None:
            self.answer.wait(5.0)
        if not self.config_up:
            raise ConfigUnavailable('no service')

    def get_config(self, joint):
        self._reach()
        with self._lock:
            return dict(self.stored[joint])

    def set_config(self, joint, values):
        self._reach()
        with self._lock:
            self.requests.append((joint, dict(values)))
            old = self.stored[joint]
            if self.refusal:
                return SetAnswer(False, self.refusal, dict(old))
            try:
                self.stored[joint] = config_store.check_request(old, joint, list(values),
                                                                list(values.values()))
            except config_store.InvalidSetting as error:
                return SetAnswer(False, str(error), dict(old))
            return SetAnswer(True, '', dict(self.stored[joint]))


@pytest.fixture
def client():
    return FakeClient()


@pytest.fixture
def window(qtbot, client):
    win = Window(client, debug_mode=True)
    qtbot.addWidget(win)
    win.show()
    return win


def background(item):
    return item.background().color().name()


def test_main_tab_shows_injected_state(window, client):
    arm = client.state
    arm.on_heartbeat(99.5)
    for joint, status in enumerate(['Working', 'Uncalibrated', 'Disconnected'] + ['Working'] * 4):
        arm.on_status(joint, status)
        arm.on_angle(joint, 0.1 * joint, 99.9)
        arm.on_voltage(joint, -1.5, 99.9)
    arm.on_gripper(3, 0.98)
    arm.on_button(2)
    window.frame()
    tab = window.main_tab
    table = tab.joint_table
    assert [table.item(r, 0).text() for r in range(3)] == ['Working', 'Uncalibrated',
                                                           'Disconnected']
    assert background(table.item(0, 0)) == QtGui.QColor(look.GREEN).name()
    assert background(table.item(1, 0)) == QtGui.QColor(look.AMBER).name()
    assert background(table.item(2, 0)) == QtGui.QColor(look.RED).name()
    assert table.item(4, 1).text() == '+0.400'
    assert table.item(4, 2).text() == '-1.50'
    assert tab.gripper_table.item(3, 0).text() == '+0.980'
    assert tab.gripper_table.item(0, 0).text() == '—'
    assert 'held: 2' in tab.button_label.text()
    assert '0.5 s ago' in tab.heartbeat_label.text()
    assert look.GREEN in tab.heartbeat_label.styleSheet()
    assert tab.teleop_label.text() == 'no arm controller'
    assert 'no serial link diagnostics for /puppet/arm_R' in tab.link_label.text()


def test_stale_heartbeat_turns_red(window, client):
    client.state.on_heartbeat(90.0)
    window.frame()
    label = window.main_tab.heartbeat_label
    assert '10.0 s ago' in label.text() and look.RED in label.styleSheet()


def test_teleop_and_serial_link(window, client):
    client.state.on_teleop(state.Teleop('following', False, True, 'hold', 0.3, 'ok', '', '',
                                        99.0))
    client.state.on_link(state.Link(2, 'serial_R: /dev/pts/3', 'no data for 3 s',
                                     (('frames dropped', '12'),), 99.0))
    window.frame()
    tab = window.main_tab
    assert 'following' in tab.teleop_label.text()
    assert tab.follow_label.text() == 'Baxter arms following: right'
    assert tab.hold_radio.isChecked() and not tab.limp_radio.isChecked()
    link = tab.link_label.text()
    assert 'ERROR' in link and 'no data for 3 s' in link and 'frames dropped: 12' in link
    assert look.RED in tab.link_label.styleSheet()
    # A link that is well shows its key values in the tooltip only: the box stays short.
    client.state.on_link(state.Link(0, 'serial_R: /dev/pts/3', 'link up',
                                    (('port', '/dev/pts/3'), ('settings loaded', 'True')), 99.0))
    window.frame()
    assert 'link up' in tab.link_label.text() and 'port' not in tab.link_label.text()
    assert tab.link_label.toolTip() == 'port: /dev/pts/3\nsettings loaded: True'


def test_each_opmode_radio_publishes_its_mode(qtbot, window, client):
    tab = window.main_tab
    for radio in (tab.hold_radio, tab.feel_radio, tab.limp_radio, tab.feel_radio):
        qtbot.mouseClick(radio, QtCore.Qt.LeftButton)
    assert client.published == [('opmode', 'hold'), ('opmode', 'feel'), ('opmode', 'limp'),
                                ('opmode', 'feel')]
    client.state.on_opmode('feel', 100.0)  # the mode arrives back: only feel is checked
    window.frame()
    assert [r.isChecked() for r in (tab.limp_radio, tab.hold_radio, tab.feel_radio)] == [
        False, False, True]


BAXTER_ARM = {'left': [0.3, -0.2, 0.5, 1.0, -0.4, 0.9, 1.2],
              'right': [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]}
PUPPET_RAD = [-0.31, -0.2, -0.6, 1.0, 0.45, 0.9, -1.5]


def robot_joints(arm_state, now_s):
    names = ['%s_%s' % (side, j) for side in ('left', 'right')
             for j in ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')]
    arm_state.on_robot_joints(names, BAXTER_ARM['left'] + BAXTER_ARM['right'], now_s)


def feel_teleop(follow_left, follow_right, zone_left='', zone_right='', received_s=99.0):
    return state.Teleop('following', follow_left, follow_right, 'feel', 0.1, '', zone_left,
                        zone_right, received_s)


def column(table, col):
    return [table.item(row, col).text() for row in range(table.rowCount())]


def test_error_columns_compare_with_the_mirrored_arm_the_puppet_drives(window, client):
    arm = client.state
    for joint, angle in enumerate(PUPPET_RAD):
        arm.on_angle(joint, angle, 99.9)
    robot_joints(arm, 99.9)
    arm.on_teleop(feel_teleop(True, False))  # puppet R drives Baxter's left arm: mirrored
    window.frame()
    table = window.main_tab.joint_table
    assert table.horizontalHeaderItem(main_tab.BAXTER_COLUMN).text() == \
        'Baxter (rad)\nleft, mirrored'
    assert column(table, main_tab.BAXTER_COLUMN) == [
        '-0.300', '-0.200', '-0.500', '+1.000', '+0.400', '+0.900', '-1.200']
    # puppet - mirrored Baxter; an unmirrored comparison would give -0.61, -1.10, +0.85, -2.70
    assert column(table, main_tab.ERROR_COLUMN) == [
        '-0.010', '+0.000', '-0.100', '+0.000', '+0.050', '+0.000', '-0.300']
    colours = [background(table.item(r, main_tab.ERROR_COLUMN)) for r in (0, 2, 6)]
    assert colours == [QtGui.QColor(c).name() for c in (look.GREEN, look.AMBER,
                                                        look.RED)]
    arm.on_teleop(feel_teleop(True, True))  # both follow: its own side, as is
    window.frame()
    assert table.horizontalHeaderItem(main_tab.BAXTER_COLUMN).text() == \
        'Baxter (rad)\nright arm'
    assert column(table, main_tab.ERROR_COLUMN)[6] == '-1.500'
    hold = feel_teleop(False, False)._replace(opmode='hold')
    arm.on_teleop(hold)  # neither follows, in hold: numbers, but no judgement
    window.frame()
    assert column(table, main_tab.ERROR_COLUMN)[6] == '-1.500'
    assert background(table.item(6, main_tab.ERROR_COLUMN)) == background(table.item(6, 1))
    arm.on_teleop(feel_teleop(False, False))  # in feel the puppet pulls toward it: judged
    window.frame()
    assert background(table.item(6, main_tab.ERROR_COLUMN)) == QtGui.QColor(look.RED).name()
    arm.on_teleop(feel_teleop(True, True))
    client.time_s = 101.5  # Baxter's pose is 1.6 s old: not shown
    window.frame()
    assert set(column(table, main_tab.ERROR_COLUMN)) == {'—'}
    assert 'unknown' in window.main_tab.tracking_label.text()


def test_every_row_of_the_joint_table_shows_under_the_two_line_header(window):
    table = window.main_tab.joint_table
    last = table.rowCount() - 1
    assert table.rowViewportPosition(last) + table.rowHeight(last) <= table.viewport().height()


def test_the_line_names_the_zone_or_says_baxter_lags(window, client):
    arm, tab = client.state, window.main_tab
    for joint, angle in enumerate(PUPPET_RAD):
        arm.on_angle(joint, angle, 99.9)
    robot_joints(arm, 100.0)
    arm.on_teleop(feel_teleop(True, False, zone_left='patient head'))
    window.frame()
    assert tab.tracking_label.text() == "keep-out zone 'patient head' holds back Baxter's left arm"
    assert look.AMBER in tab.tracking_label.styleSheet()
    arm.on_teleop(feel_teleop(True, False))  # out of the zone; joint 6 still 0.3 rad off
    window.frame()
    assert tab.tracking_label.text() == 'Baxter tracks the puppet'  # not for long yet
    client.time_s = 100.6
    robot_joints(arm, 100.6)
    arm.on_teleop(feel_teleop(True, False, received_s=100.5))  # arm_X reports every 0.5 s
    window.frame()
    client.time_s = 101.1
    robot_joints(arm, 101.1)
    arm.on_teleop(feel_teleop(True, False, received_s=101.0))
    window.frame()
    assert tab.tracking_label.text() == 'Baxter lags: left arm, joint 6 off by -0.30 rad'
    assert look.RED in tab.tracking_label.styleSheet()
    arm.on_angle(6, -1.2, 101.1)  # the puppet gives way: caught up
    window.frame()
    assert tab.tracking_label.text() == 'Baxter tracks the puppet'


def test_only_the_visible_tab_redraws(window, client):
    client.state.on_angle(2, 0.3, 99.0)
    client.state.on_angle(2, 0.4, 100.0)
    window.frame()
    curve = window.joint_tabs[2].angle_plot.getPlotItem().listDataItems()[0]
    assert curve.xData is None or len(curve.xData) == 0  # hidden tab: not drawn
    window.tabs.setCurrentWidget(window.joint_tabs[2])
    client.state.on_status(0, 'Working')
    window.frame()
    assert list(curve.xData) == [-1.0, 0.0] and list(curve.yData) == pytest.approx([0.3, 0.4])
    assert '+0.400 rad' in window.joint_tabs[2].now_label.text()
    assert window.main_tab.joint_table.item(0, 0).text() == '—'  # main tab hidden: not redrawn


def fill(tab, **changes):
    for name, field in tab.fields.items():
        field.setText(changes.get(name, config_store.format_value(settings.DEFAULTS[name])))


def read_tab(qtbot, client, joint):
    """Return a joint tab that has read the stored settings (Get)."""
    tab = joint_tab.JointTab(client, joint)
    qtbot.addWidget(tab)
    tab.get()
    qtbot.waitUntil(lambda: not tab.busy(), timeout=3000)
    assert tab.message.text().startswith('read the stored settings')
    return tab


def set_and_wait(qtbot, tab):
    qtbot.mouseClick(tab.set_button, QtCore.Qt.LeftButton)
    qtbot.waitUntil(lambda: not tab.busy(), timeout=5000)


@pytest.mark.parametrize('changes, words', [
    ({'pid_kp': 'fast'}, 'not a number'),
    ({'angle_min': '1', 'angle_max': '0.5'}, 'above angle_max'),
    ({'sign_angle': '2'}, 'sign'),
    ({'voltage_max': '9'}, 'outside its bound'),
])
def test_invalid_entry_is_refused_with_a_message_and_nothing_is_sent(qtbot, client, changes,
                                                                    words):
    tab = read_tab(qtbot, client, 4)
    fill(tab, **changes)
    qtbot.mouseClick(tab.set_button, QtCore.Qt.LeftButton)
    assert client.requests == [] and not tab.busy()
    assert words in tab.message.text() and 'refused' in tab.message.text()
    assert tab.message.styleSheet() == joint_tab.ERROR_STYLE


def test_set_sends_the_edited_fields_in_one_request_and_shows_what_is_stored(qtbot, client):
    tab = read_tab(qtbot, client, 1)
    client.stored[1]['pid_kd'] = 0.25  # someone else changes a setting meanwhile
    # a new minimum above the stored maximum, with the new maximum: one request takes both
    fill(tab, angle_min='2', angle_max='3', pid_ki='0.50')
    set_and_wait(qtbot, tab)
    assert tab.message.text().startswith('saved'), tab.message.text()
    assert tab.message.styleSheet() == joint_tab.OK_STYLE
    assert client.requests == [(1, {'angle_min': 2.0, 'angle_max': 3.0, 'pid_ki': 0.5})]
    assert client.stored[1]['pid_kd'] == 0.25, 'a field not edited is not sent'
    shown = {name: field.text() for name, field in tab.fields.items()}
    assert shown == {name: settings_form.field_text(value)
                     for name, value in client.stored[1].items()}
    assert shown['pid_ki'] == '0.5' and shown['pid_kd'] == '0.25'
    set_and_wait(qtbot, tab)  # what Set stored is no longer an edit
    assert len(client.requests) == 1 and 'no change' in tab.message.text()


def test_a_field_typed_into_while_set_waits_keeps_the_new_text(qtbot, client):
    tab = read_tab(qtbot, client, 0)
    tab.fields['pid_kp'].setText('1.50')
    client.answer = threading.Event()  # set_config waits until it is set
    qtbot.mouseClick(tab.set_button, QtCore.Qt.LeftButton)
    assert tab.busy()
    tab.fields['pid_kd'].setText('0.3')  # typed while the call is under way
    client.answer.set()
    qtbot.waitUntil(lambda: not tab.busy(), timeout=3000)
    assert tab.message.text().startswith('saved') and client.requests == [(0, {'pid_kp': 1.5})]
    assert tab.fields['pid_kp'].text() == '1.5', 'what was sent shows as stored'
    assert tab.fields['pid_kd'].text() == '0.3', 'the unsaved edit stays'
    set_and_wait(qtbot, tab)
    assert client.requests[-1] == (0, {'pid_kd': config_store.to_float32(0.3)})


def test_a_request_the_config_node_refuses_keeps_the_edits_and_shows_why(qtbot, client):
    tab = read_tab(qtbot, client, 3)
    client.stored[3]['angle_max'] = 0.5  # changed elsewhere: the form still shows 1.571
    fill(tab, angle_min='1', pid_kp='2')
    set_and_wait(qtbot, tab)
    assert client.requests == [(3, {'angle_min': 1.0, 'pid_kp': 2.0})]
    assert 'refused by config_R' in tab.message.text()
    assert 'joint 3 angle_min = 1.0: above angle_max = 0.5' in tab.message.text()
    assert tab.message.styleSheet() == joint_tab.ERROR_STYLE
    assert tab.fields['angle_min'].text() == '1' and tab.fields['pid_kp'].text() == '2'
    assert tab.fields['angle_max'].text() == '1.571', 'the refusal does not refill the form'
    assert client.stored[3]['pid_kp'] == 0.0, 'all or none'
    client.refusal = 'changes will not persist (cannot repair arm_R.ini: Read-only file system)'
    fill(tab, pid_kp='3')
    set_and_wait(qtbot, tab)
    assert 'changes will not persist' in tab.message.text()
    assert tab.fields['pid_kp'].text() == '3'


def test_set_needs_the_settings_read_first(qtbot, client):
    client.config_up = False
    tab = joint_tab.JointTab(client, 2)
    qtbot.addWidget(tab)
    tab.get()
    qtbot.waitUntil(lambda: not tab.busy(), timeout=3000)
    assert 'config node not reachable' in tab.message.text()
    client.config_up = True
    fill(tab, pid_kp='0.5')
    qtbot.mouseClick(tab.set_button, QtCore.Qt.LeftButton)
    assert client.requests == [] and 'Get' in tab.message.text()


def test_get_fills_fields_and_reports_a_missing_config_node(qtbot, client):
    client.stored[5]['pid_kd'] = 0.125
    tab = joint_tab.JointTab(client, 5)
    qtbot.addWidget(tab)
    qtbot.mouseClick(tab.get_button, QtCore.Qt.LeftButton)
    qtbot.waitUntil(lambda: not tab.busy(), timeout=3000)
    assert tab.fields['pid_kd'].text() == '0.125'
    assert tab.fields['angle_max'].text() == '1.571'
    client.config_up = False
    tab.fields['pid_kd'].setText('0.5')
    set_and_wait(qtbot, tab)
    assert 'config node not reachable' in tab.message.text() and client.requests == []
    assert tab.fields['pid_kd'].text() == '0.5'


def join_config_calls():
    """Wait until every config call's worker thread has ended, its answer queued to Qt."""
    for thread in threading.enumerate():
        if thread.name == 'config call':
            thread.join(5.0)
            assert not thread.is_alive()


@pytest.mark.parametrize('button', ['get_button', 'set_button'])
def test_a_hung_config_node_does_not_freeze_the_window(qtbot, client, monkeypatch, button):
    monkeypatch.setattr(joint_tab, 'CALL_TIMEOUT_S', 0.3)
    tab = read_tab(qtbot, client, 6)
    tab.fields['pid_kp'].setText('0.5')
    client.answer = threading.Event()  # the config calls hang until it is set (or 5 s)
    qtbot.mouseClick(getattr(tab, button), QtCore.Qt.LeftButton)
    # the click returned while the call still hangs: the GUI thread was not blocked
    assert tab.busy() and ('reading' in tab.message.text() or 'sending' in tab.message.text())
    assert not tab.get_button.isEnabled() and not tab.set_button.isEnabled()
    qtbot.waitUntil(lambda: not tab.busy(), timeout=3000)
    assert 'no answer within 0.3 s' in tab.message.text() and tab.get_button.isEnabled()
    client.answer.set()  # the late answer is dropped
    join_config_calls()
    QtCore.QCoreApplication.processEvents()
    assert tab.fields['pid_kp'].text() == '0.5' and 'no answer' in tab.message.text()


def test_setpoint_is_checked_against_the_stored_limits(qtbot, client):
    tab = read_tab(qtbot, client, 0)
    tab.setpoint_field.setText('2.0')
    qtbot.mouseClick(tab.setpoint_button, QtCore.Qt.LeftButton)
    assert client.published == [] and 'outside the angle limits' in tab.message.text()
    tab.setpoint_field.setText('-0.25')
    qtbot.mouseClick(tab.setpoint_button, QtCore.Qt.LeftButton)
    assert client.published == [('setpoint', 0, -0.25)]


def test_joint_plot_has_the_newest_sample_at_the_right(window, client):
    window.tabs.setCurrentWidget(window.joint_tabs[0])
    for i in range(50):
        client.state.on_voltage(0, float(i), 90.0 + i * 0.2)
    client.time_s = 99.8
    window.frame()
    curve = window.joint_tabs[0].voltage_plot.getPlotItem().listDataItems()[0]
    assert curve.xData[-1] == pytest.approx(0.0) and curve.yData[-1] == 49.0
    assert curve.xData[0] == pytest.approx(-9.8)  # all 10 s shown
    assert window.windowTitle() == 'RoboPuppet — arm R'


class FakeSim:
    def __init__(self):
        self.hands, self.buttons, self.grippers = [], [], []

    def set_hand(self, angles_rad):
        self.hands.append(list(angles_rad))

    def set_button(self, button):
        self.buttons.append(button)

    def set_grippers(self, readings):
        self.grippers.append(list(readings))


def test_virtual_puppet_panel_publishes_hand_buttons_and_end_piece(qtbot, client):
    sim = FakeSim()
    win = Window(client, debug_mode=False, sim=sim)
    qtbot.addWidget(win)
    panel = win.sim_panel
    assert sim.hands == sim.buttons == sim.grippers == []  # nothing until the operator acts
    assert panel.angles() == pytest.approx(list(REST_POSE_RAD), abs=1e-3)
    panel.set_angle(3, -1.2)
    assert sim.hands[-1] == pytest.approx([*REST_POSE_RAD[:3], -1.2, *REST_POSE_RAD[4:]],
                                          abs=1e-3)
    panel.joint_sliders[6].setValue(panel.joint_sliders[6].maximum())
    assert sim.hands[-1][6] == pytest.approx(3.1416, abs=1e-3)
    qtbot.mouseClick(panel.let_go_button, QtCore.Qt.LeftButton)
    assert all(math.isnan(a) for a in sim.hands[-1])
    panel.set_angle(0, 0.5)  # the hand takes joint 0 again, and only joint 0
    assert sim.hands[-1][0] == 0.5 and all(math.isnan(a) for a in sim.hands[-1][1:])
    qtbot.mousePress(panel.user_buttons[1], QtCore.Qt.LeftButton)
    assert sim.buttons[-1] == 2
    qtbot.mouseRelease(panel.user_buttons[1], QtCore.Qt.LeftButton)
    qtbot.waitUntil(lambda: sim.buttons[-1] == 0, timeout=1000)  # held MIN_PRESS_S at least
    qtbot.mousePress(panel.end_piece_button, QtCore.Qt.LeftButton)
    assert sim.grippers[-1] == [0.0, 0.0, 0.0, 0.0]  # end piece pressed
    qtbot.mouseRelease(panel.end_piece_button, QtCore.Qt.LeftButton)
    qtbot.waitUntil(lambda: sim.grippers[-1] == [0.0, 0.0, 0.0, 1.0], timeout=1000)
    panel.gripper_sliders[1].setValue(40)
    assert sim.grippers[-1] == [0.0, 0.4, 0.0, 1.0]
    assert win.joint_tabs == [] and win.tabs.count() == 2  # main and calibration
