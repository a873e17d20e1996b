"""The "Link to the robot room" box: the pure decision (link_view) and the widget (pytest-qt)."""
import os

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402

from robopuppet.gui import link_box, link_view, look, main_tab, state  # noqa: E402
from robopuppet.gui.link_view import ERROR, NETWORK, OK, OPERATOR, ROBOT, UNHEARD, WARN  # noqa
from robopuppet.gui.window import Window  # noqa: E402
from robopuppet_msgs.msg import LinkState  # noqa: E402

NOW_S = 100.0


def robot_link(received_s=NOW_S - 0.1, level=OK, fault='none', detail='', rtt_s=0.104,
               sample_age_s=0.062, max_sample_age_s=0.35, clock_known=True, loss=0.0):
    return state.RobotLink(rtt_s, sample_age_s, max_sample_age_s, clock_known, loss, level,
                           fault, detail, received_s)


def snapshot(robot=None, serial_level=0, serial_received_s=NOW_S - 0.5,
             heartbeat_s=NOW_S - 0.5):
    """A Snapshot of a healthy puppet (serial link OK, fresh heartbeat) and the given link."""
    serial = None if serial_level is None else state.Link(
        serial_level, 'serial_R: puppet serial link',
        'device silent' if serial_level == ERROR else 'link up', (), serial_received_s)
    arm = state.ArmState()
    arm.on_link(serial)
    if heartbeat_s is not None:
        arm.on_heartbeat(heartbeat_s)
    if robot is not None:
        arm.on_robot_link(robot)
    return arm.snapshot()


def test_the_fault_names_are_linkstates_constants():
    assert (link_view.NONE, OPERATOR, NETWORK, ROBOT) == (
        LinkState.NONE, LinkState.OPERATOR, LinkState.NETWORK, LinkState.ROBOT)


def test_a_healthy_link_is_green_with_its_figures():
    view = link_view.describe(snapshot(robot_link(loss=0.04)), NOW_S)
    assert view.level == OK and view.side == link_view.NONE
    assert view.status == 'Link to the robot room: OK'
    assert view.rtt == 'Round trip: 104 ms'
    assert view.delay == 'Delay to Baxter: 62 ms (limit 350 ms)'
    assert view.loss == 'Pings lost: 4 % in the last few seconds'
    assert view.where == 'Problem: none'


def test_never_heard_is_red_and_blames_the_network_or_the_robot_room():
    view = link_view.describe(snapshot(None), NOW_S)
    assert view.level == ERROR and view.side == UNHEARD
    assert view.status == ("No link to the robot room: nothing heard yet; the network or the "
                           "robot room's computer is down")
    assert view.full_status == view.status
    assert (view.rtt, view.delay, view.loss) == ('Round trip: —', 'Delay to Baxter: —',
                                                 'Pings lost: —')
    assert view.where == 'Problem: network or robot room'


@pytest.mark.parametrize('age_s, fresh', [(0.0, True), (0.99, True), (1.01, False), (30.0, False)])
def test_a_link_state_older_than_1_s_turns_red_whatever_it_said(age_s, fresh):
    view = link_view.describe(snapshot(robot_link(received_s=NOW_S - age_s)), NOW_S)
    if fresh:
        assert view.level == OK and view.rtt == 'Round trip: 104 ms'
    else:
        assert view.level == ERROR and view.side == UNHEARD
        assert 'nothing heard for %s' % link_view.duration(age_s) in view.status
        assert view.rtt == 'Round trip: —'  # no old figure passed off as current


def test_silence_with_a_sick_puppet_names_both_sides():
    view = link_view.describe(snapshot(None, serial_level=ERROR), NOW_S)
    assert view.level == ERROR and view.side == UNHEARD
    assert view.full_status.endswith('is down. In this room too, puppet serial link: device '
                                     'silent')
    assert view.status == link_view.shorten(view.full_status) != view.full_status
    assert view.where == 'Problem: network or robot room, and this room (puppet)'


@pytest.mark.parametrize('level, headline', [(WARN, 'Network slow'),
                                             (ERROR, 'Network failing')])
def test_a_network_fault_with_a_healthy_puppet_stays_on_the_network(level, headline):
    detail = 'samples 310 ms old (limit 350 ms), Baxter stopped'
    view = link_view.describe(snapshot(robot_link(level=level, fault=NETWORK, detail=detail,
                                                  sample_age_s=0.31)), NOW_S)
    assert view.level == level and view.side == NETWORK
    assert view.status == '%s: %s' % (headline, detail)
    assert view.delay == 'Delay to Baxter: 310 ms (limit 350 ms)'
    assert view.where == 'Problem: network'


@pytest.mark.parametrize('puppet, found', [
    (dict(serial_level=ERROR), 'puppet serial link: device silent'),
    (dict(serial_received_s=NOW_S - 6.0), "the puppet's serial link has not reported for 6.0 s"),
    (dict(heartbeat_s=NOW_S - 3.0), 'the puppet is silent (no heartbeat for 3.0 s)'),
])
def test_a_network_fault_with_a_sick_puppet_is_put_on_this_room(puppet, found):
    view = link_view.describe(snapshot(robot_link(level=ERROR, fault=NETWORK, detail='late'),
                                       **puppet), NOW_S)
    assert view.level == ERROR and view.side == OPERATOR
    assert view.status == 'Problem in this room (the puppet): late; ' + found
    assert view.where == 'Problem: this room (puppet)'


@pytest.mark.parametrize('puppet', [dict(serial_level=WARN), dict(serial_level=None),
                                    dict(heartbeat_s=None),
                                    dict(heartbeat_s=NOW_S - 2.4)])
def test_a_puppet_that_is_merely_unknown_or_warned_is_not_blamed(puppet):
    view = link_view.describe(snapshot(robot_link(level=WARN, fault=NETWORK), **puppet), NOW_S)
    assert view.side == NETWORK and link_view.puppet_problem(snapshot(**puppet), NOW_S) is None


def test_a_robot_fault_stays_in_the_robot_room_even_with_a_sick_puppet():
    link = robot_link(level=ERROR, fault=ROBOT, detail='Baxter is disabled')
    for puppet in (dict(), dict(serial_level=ERROR)):
        view = link_view.describe(snapshot(link, **puppet), NOW_S)
        assert view.level == ERROR and view.side == ROBOT
        assert view.status == 'Problem in the robot room: Baxter is disabled'
        assert view.where == 'Problem: robot room (Baxter)'


def test_an_operator_fault_from_the_robot_host_is_this_rooms():
    view = link_view.describe(snapshot(robot_link(level=ERROR, fault=OPERATOR,
                                                  detail='no puppet samples')), NOW_S)
    assert view.side == OPERATOR and view.status == ('Problem in this room (the puppet): '
                                                     'no puppet samples')


def test_figures_not_measured_yet_say_so():
    view = link_view.describe(snapshot(robot_link(rtt_s=-1.0, sample_age_s=-1.0)), NOW_S)
    assert view.rtt == 'Round trip: not measured yet'
    assert view.delay == 'Delay to Baxter: no puppet data received yet'
    view = link_view.describe(snapshot(robot_link(clock_known=False)), NOW_S)
    assert view.delay == 'Delay to Baxter: not known yet'
    view = link_view.describe(snapshot(robot_link(loss=float('nan'), rtt_s=1.5)), NOW_S)
    assert view.loss == 'Pings lost: —' and view.rtt == 'Round trip: 1.5 s'


def test_nonsense_from_the_robot_host_is_red_or_named_not_hidden():
    view = link_view.describe(snapshot(robot_link(level=7)), NOW_S)
    assert view.level == ERROR and 'unreadable: level 7' in view.status
    view = link_view.describe(snapshot(robot_link(level=WARN, fault='gremlins', detail='x')),
                              NOW_S)
    assert view.level == WARN and view.status == 'Link problem: x'
    assert view.where == "Problem: not known (the robot room says 'gremlins')"


@pytest.mark.parametrize('text, shown', [
    ('x' * 100, 'x' * 100),
    ('word ' * 30, ('word ' * 20).rstrip() + '…'),  # 99 characters and the ellipsis
    ('long; detail, ' + 'y' * 200, 'long; detail…'),
    ('z' * 150, 'z' * 99 + '…'),
])
def test_long_statuses_are_cut_at_a_word_within_the_limit(text, shown):
    assert link_view.shorten(text) == shown and len(shown) <= link_view.STATUS_MAX_CHARS


@pytest.mark.parametrize('seconds, text', [(0.0621, '62 ms'), (0.9994, '999 ms'), (1.44, '1.4 s'),
                                           (12.3, '12 s'), (-1.0, '—'), (float('nan'), '—')])
def test_durations_read_naturally(seconds, text):
    assert link_view.duration(seconds) == text


# --- the widget, on the main tab --------------------------------------------------------------

def test_box_colours_are_the_main_tabs():
    assert link_box.LEVEL_COLOUR == {OK: look.GREEN, WARN: look.AMBER,
                                     ERROR: look.RED}


@pytest.fixture
def window(qtbot):
    from test_gui_widgets import FakeClient
    client = FakeClient()
    client.time_s = NOW_S
    win = Window(client, debug_mode=False)
    qtbot.addWidget(win)
    win.show()
    return win


def shown(box):
    return [label.text() for label in (box.status_label, box.rtt_label, box.delay_label,
                                       box.loss_label, box.where_label)]


def test_the_main_tab_shows_the_link_and_turns_red_when_it_goes_quiet(window):
    box = window.main_tab.link_box
    arm = window.client.state
    window.frame()
    assert box.isVisible() and box.title() == 'Link to the robot room'
    assert box.status_label.text().startswith('No link to the robot room')
    assert look.RED in box.status_label.styleSheet()
    arm.on_heartbeat(NOW_S - 0.2)
    arm.on_robot_link(robot_link(received_s=NOW_S - 0.1))
    window.frame()
    assert shown(box) == ['Link to the robot room: OK', 'Round trip: 104 ms',
                          'Delay to Baxter: 62 ms (limit 350 ms)',
                          'Pings lost: 0 % in the last few seconds', 'Problem: none']
    assert look.GREEN in box.status_label.styleSheet()
    arm.on_robot_link(robot_link(level=WARN, fault=NETWORK, detail='samples 310 ms old'))
    window.frame()
    assert box.status_label.text() == 'Network slow: samples 310 ms old'
    assert look.AMBER in box.status_label.styleSheet()
    window.client.time_s = NOW_S + 2.0  # link_state stops; the puppet's heartbeat is 2.2 s old
    window.frame()
    assert box.status_label.text().startswith('No link to the robot room: nothing heard for '
                                              '2.1 s')
    assert look.RED in box.status_label.styleSheet()
    assert box.where_label.text() == 'Problem: network or robot room'


def test_the_box_fits_the_main_tab_without_clipping(qtbot, window):
    arm = window.client.state
    arm.on_robot_link(robot_link(level=ERROR, fault=NETWORK, detail=(
        'samples 420 ms old (limit 350 ms), 12 % of pings lost: Baxter stopped following')))
    arm.on_link(state.Link(ERROR, 'serial_R: puppet serial link', 'device silent', (), NOW_S))
    window.frame()
    qtbot.wait(50)  # the layout settles on the event loop
    box = window.main_tab.link_box
    for label in (box.status_label, box.delay_label, box.where_label):
        assert label.height() >= label.heightForWidth(label.width()), label.text()
        assert label.width() <= box.width()
