"""pytest-qt tests of the GUI widgets, fed by injected ArmState data and a fake client."""
import math
import os
import threading

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402
from PyQt5 import QtCore, QtGui  # noqa: E402

from robopuppet import settings  # noqa: E402
from robopuppet.config import config_store  # noqa: E402
from robopuppet.gui import joint_tab, main_tab, state  # noqa: E402
from robopuppet.gui.puppet_client import ConfigUnavailable  # noqa: E402
from robopuppet.gui.window import Window  # noqa: E402
from robopuppet.puppet_sim.puppet_model import REST_POSE_RAD  # noqa: E402


class FakeClient:
    """Stands in for PuppetClient: records what would be published, stores like config_X.

    Like ROS across topics it keeps no order: published settings wait until the next get_config
    and are then applied newest first (a refused one is dropped, as config_X drops it).
    """

    side = 'R'

    def __init__(self):
        self.state = state.ArmState()
        self.time_s = 100.0
        self.published = []
        self.config_up = True
        self.answer = None  # a threading.Event that get_config waits for (at most 5 s)
        self.stored = config_store.defaults()
        self._undelivered = []
        self._lock = threading.Lock()

    def now(self):
        return self.time_s

    def set_opmode(self, opmode):
        self.published.append(('opmode', opmode))

    def set_setpoint(self, joint, angle_rad):
        self.published.append(('setpoint', joint, angle_rad))

    def set_setting(self, joint, name, value):
        with self._lock:
            self.published.append((name, joint, value))
            self._undelivered.append((joint, name, value))

    def get_config(self, joint):
        if self.answer is not None:
            self.answer.wait(5.0)
        if not self.config_up:
            raise ConfigUnavailable('no service')
        with self._lock:
            for other, name, value in reversed(self._undelivered):
                try:
                    self.stored[other][name] = config_store.validate(self.stored[other], other,
                                                                     name, value)
                except config_store.InvalidSetting:
                    pass
            del self._undelivered[:]
            return dict(self.stored[joint])


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
    assert background(table.item(0, 0)) == QtGui.QColor(main_tab.GREEN).name()
    assert background(table.item(1, 0)) == QtGui.QColor(main_tab.AMBER).name()
    assert background(table.item(2, 0)) == QtGui.QColor(main_tab.RED).name()
    assert table.item(4, 1).text() == '+0.400'
    assert table.item(4, 2).text() == '-1.50'
    assert tab.gripper_table.item(3, 0).text() == '+0.980'
    assert tab.gripper_table.item(0, 0).text() == '—'
    assert 'held: 2' in tab.button_label.text()
    assert '0.5 s ago' in tab.heartbeat_label.text()
    assert main_tab.GREEN in tab.heartbeat_label.styleSheet()
    assert tab.teleop_label.text() == 'no arm controller'
    assert 'no diagnostics from serial_R' in tab.link_label.text()


def test_stale_heartbeat_turns_red(window, client):
    client.state.on_heartbeat(90.0)
    window.frame()
    label = window.main_tab.heartbeat_label
    assert '10.0 s ago' in label.text() and main_tab.RED in label.styleSheet()


def test_teleop_and_serial_link(window, client):
    client.state.on_teleop(state.Teleop('following', False, True, 'hold', 0.3, 'ok', 99.0))
    client.state.on_link(state.Link(2, 'serial_R: /dev/pts/3', 'no data for 3 s',
                                     (('frames dropped', '12'),), 99.0))
    window.frame()
    tab = window.main_tab
    assert 'following' in tab.teleop_label.text()
    assert tab.follow_label.text() == 'Baxter arms following: right'
    assert tab.hold_radio.isChecked() and not tab.limp_radio.isChecked()
    link = tab.link_label.text()
    assert 'ERROR' in link and 'no data for 3 s' in link and 'frames dropped: 12' in link
    assert main_tab.RED in tab.link_label.styleSheet()


def test_opmode_radio_publishes(qtbot, window, client):
    qtbot.mouseClick(window.main_tab.hold_radio, QtCore.Qt.LeftButton)
    assert client.published == [('opmode', 'hold')]


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
])
def test_invalid_entry_is_refused_with_a_message(qtbot, client, changes, words):
    tab = read_tab(qtbot, client, 4)
    fill(tab, **changes)
    qtbot.mouseClick(tab.set_button, QtCore.Qt.LeftButton)
    assert client.published == [] and not tab.busy()
    assert words in tab.message.text() and 'refused' in tab.message.text()
    assert tab.message.styleSheet() == joint_tab.ERROR_STYLE


@pytest.mark.parametrize('changes, phases', [
    ({'angle_min': '2', 'angle_max': '3', 'pid_kp': '0.5'},
     [['angle_max', 'pid_kp'], ['angle_min']]),  # the new minimum is above the stored maximum
    ({'angle_min': '-3', 'angle_max': '-2'}, [['angle_min'], ['angle_max']]),
    ({'angle_min': '-1', 'angle_max': '1'}, [['angle_min', 'angle_max']]),
])
def test_set_publishes_in_phases_that_any_delivery_order_accepts(qtbot, client, changes,
                                                                  phases):
    tab = read_tab(qtbot, client, 1)
    fill(tab, **changes)
    set_and_wait(qtbot, tab)
    assert tab.message.text().startswith('saved'), tab.message.text()
    assert [p[0] for p in client.published] == [name for phase in phases for name in phase]
    for name, text in changes.items():
        assert client.stored[1][name] == config_store.to_float32(float(text))


def test_set_sends_only_the_fields_edited_since_get(qtbot, client):
    tab = read_tab(qtbot, client, 3)
    client.stored[3]['pid_ki'] = 0.25  # someone else changes a setting meanwhile
    tab.fields['pid_kp'].setText('0.5')
    set_and_wait(qtbot, tab)
    assert client.published == [('pid_kp', 3, 0.5)]
    assert client.stored[3]['pid_ki'] == 0.25 and tab.message.text().startswith('saved')
    set_and_wait(qtbot, tab)  # what Set sent is no longer an edit
    assert len(client.published) == 1 and 'no change' in tab.message.text()


def test_set_refuses_an_edit_that_clashes_with_a_setting_changed_elsewhere(qtbot, client):
    tab = read_tab(qtbot, client, 3)
    client.stored[3]['angle_max'] = 0.5
    tab.fields['angle_min'].setText('1')
    set_and_wait(qtbot, tab)
    assert client.published == [] and 'changed since they were read' in tab.message.text()


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
    assert client.published == [] and 'Get' in tab.message.text()


def test_set_reports_a_value_the_config_node_did_not_store(qtbot, client):
    tab = read_tab(qtbot, client, 1)
    client.set_setting = lambda joint, name, value: client.published.append(name)  # drops all
    tab.fields['pid_ki'].setText('0.2')
    set_and_wait(qtbot, tab)
    assert client.published == ['pid_ki']
    assert 'not stored' in tab.message.text() and 'pid_ki is 0' in tab.message.text()


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
    assert 'config node not reachable' in tab.message.text() and client.published == []


def test_a_hung_config_node_does_not_freeze_the_window(qtbot, client, monkeypatch):
    monkeypatch.setattr(joint_tab, 'READ_TIMEOUT_S', 0.3)
    client.answer = threading.Event()  # get_config hangs until it is set (or 5 s)
    tab = joint_tab.JointTab(client, 6)
    qtbot.addWidget(tab)
    qtbot.mouseClick(tab.get_button, QtCore.Qt.LeftButton)
    # the click returned while get_config still hangs: the GUI thread was not blocked
    assert tab.busy() and 'reading' in tab.message.text()
    assert not tab.get_button.isEnabled() and not tab.set_button.isEnabled()
    qtbot.waitUntil(lambda: not tab.busy(), timeout=3000)
    assert 'no answer within 0.3 s' in tab.message.text() and tab.get_button.isEnabled()
    client.answer.set()  # the late answer is dropped
    qtbot.wait(200)
    assert tab.fields['angle_max'].text() == '' and 'no answer' in tab.message.text()


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
    assert sim.buttons[-1] == 0
    qtbot.mousePress(panel.end_piece_button, QtCore.Qt.LeftButton)
    assert sim.grippers[-1] == [0.0, 0.0, 0.0, 0.0]  # end piece pressed
    qtbot.mouseRelease(panel.end_piece_button, QtCore.Qt.LeftButton)
    assert sim.grippers[-1] == [0.0, 0.0, 0.0, 1.0]
    panel.gripper_sliders[1].setValue(40)
    assert sim.grippers[-1] == [0.0, 0.4, 0.0, 1.0]
    assert win.joint_tabs == [] and win.tabs.count() == 1
