"""pytest-qt tests of the main tab's Assist box: hidden until the assist reports, each state's
look, the buttons publish, staleness; and the client's assist topics (publishers faked)."""
import os
import threading
import types

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402

from robopuppet import interface  # noqa: E402
from robopuppet.gui import assist_box, freshness, look  # noqa: E402
from robopuppet.gui.command_topics import CommandTopics  # noqa: E402
from robopuppet.gui.assist_topics import Assist, AssistTopics  # noqa: E402
from robopuppet.gui.window import Window  # noqa: E402
from robopuppet_msgs.msg import AssistState  # noqa: E402
from test_gui_widgets import FakeClient  # noqa: E402

TASK = 'carry the tray with both hands and keep it level'


class AssistClient(FakeClient):
    """A FakeClient that hears the assist: assist_state() and command_assist() like the real."""

    def __init__(self):
        super().__init__()
        self.assist = None

    def assist_state(self):
        return self.assist

    def command_assist(self, command):
        self.published.append(('assist', command))

    def report(self, state, confidence=0.9, detail='', follower='left', age_s=0.0):
        self.assist = Assist(state, 'right' if follower == 'left' else 'left', follower, TASK,
                             'gmr', confidence, detail, self.time_s - age_s)


@pytest.fixture
def win(qtbot):
    window = Window(AssistClient(), debug_mode=False)
    qtbot.addWidget(window)
    window.show()
    return window


def test_the_box_is_hidden_until_the_assist_reports(win):
    win.frame()
    box = win.main_tab.assist_box
    assert not box.isVisible()
    win.client.report('ready')
    win.frame()
    assert box.isVisible()
    assert box.summary_label.text() == (
        "Assist: Baxter's left arm, from the right arm's motion (%s, gmr)" % TASK)
    assert box.hint_label.text() == 'take over: press 2 on puppet L'


@pytest.mark.parametrize('state, colour', [
    ('assisting', look.GREEN), ('holding', look.AMBER), ('stopped', look.GREY),
    ('off', look.GREY), ('ready', None)])
def test_each_state_shows_in_its_colour(win, state, colour):
    win.client.report(state, confidence=0.42,
                      detail='assist holding: unfamiliar motion' if state == 'holding' else '')
    win.frame()
    box = win.main_tab.assist_box
    assert box.state_label.text() == 'assist: %s' % state
    style = box.state_label.styleSheet()
    assert (colour in style) if colour else style == ''
    assert box.confidence_bar.value() == 42
    assert (look.AMBER in box.detail_label.styleSheet()) == (state == 'holding')
    assert box.start_button.isEnabled() == (state == 'stopped')
    assert box.stop_button.isEnabled() == (state != 'stopped')


def test_the_holding_detail_is_shown_amber(win):
    win.client.report('holding', confidence=0.1, detail='assist holding: unfamiliar motion')
    win.frame()
    box = win.main_tab.assist_box
    assert box.detail_label.text() == 'assist holding: unfamiliar motion'
    assert look.AMBER in box.detail_label.styleSheet()
    assert box.confidence_bar.value() == 10


def test_the_buttons_publish_stop_and_start(win):
    client, box = win.client, win.main_tab.assist_box
    client.report('assisting')
    win.frame()
    box.stop_button.click()
    client.report('stopped')
    win.frame()
    box.start_button.click()
    assert [p for p in client.published if p[0] == 'assist'] == [('assist', 'stop'),
                                                                 ('assist', 'start')]


def test_an_old_state_is_greyed_not_current_and_cannot_start(win):
    client, box = win.client, win.main_tab.assist_box
    client.report('stopped', age_s=assist_box.ASSIST_STALE_S + 0.5)
    win.frame()
    assert box.state_label.text() == 'assist: stopped   NOT CURRENT'
    assert box.age_label.text().startswith('NOT CURRENT: assist last heard')
    assert not box.start_button.isEnabled() and box.stop_button.isEnabled()
    client.report('holding', detail='assist holding: unfamiliar motion',
                  age_s=assist_box.ASSIST_STALE_S + 0.5)
    win.frame()
    assert look.GREY in box.state_label.styleSheet()
    assert freshness.STALE_TEXT_COLOUR in box.detail_label.styleSheet()
    assert not box.confidence_bar.isEnabled()
    client.report('holding', detail='assist holding: unfamiliar motion')
    win.frame()
    assert look.AMBER in box.state_label.styleSheet() and box.confidence_bar.isEnabled()


def test_the_take_over_hint_names_the_followers_own_puppet_and_button():
    view = assist_box.describe(Assist('assisting', 'left', 'right', '', '', 1.5, '', 0.0), 0.0)
    assert view.hint == 'take over: press 3 on puppet R'
    assert view.summary == "Assist: Baxter's right arm, from the left arm's motion"
    assert view.confidence_pct == 100


def test_the_client_keeps_the_assist_state_and_publishes_its_commands():
    fake = types.SimpleNamespace(_assist_lock=threading.Lock(), _assist=None,
                                 _assist_clock=lambda: 7.0)
    AssistTopics._on_assist(fake, AssistState(state='holding', leader='right', follower='left',
                                              task=TASK, method='lwr', confidence=0.25,
                                              detail='assist holding: unfamiliar motion'))
    assert AssistTopics.assist_state(fake) == Assist(
        'holding', 'right', 'left', TASK, 'lwr', 0.25, 'assist holding: unfamiliar motion', 7.0)
    sent = []
    fake = types.SimpleNamespace(_assist_pub=types.SimpleNamespace(
        publish=lambda msg: sent.append(msg.data)))
    CommandTopics.command_assist(fake, 'stop')
    assert sent == ['stop']
    with pytest.raises(ValueError, match='assist command must be one of'):
        CommandTopics.command_assist(fake, 'go faster')
    assert interface.ASSIST_COMMANDS == ('stop', 'start')
