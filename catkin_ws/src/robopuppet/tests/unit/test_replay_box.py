"""pytest-qt tests of the replay control in the Recording box, running the real `rosrun
robopuppet replay` and `export` commands (no ROS master: they fail or wait as they would), and
unit tests of its pure helpers (robopuppet.episodes.replay_control)."""
import os

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402
import yaml  # noqa: E402

from robopuppet.episodes import recording, replay_control as rc  # noqa: E402
from robopuppet.gui import replay_box  # noqa: E402
from robopuppet.gui.window import Window  # noqa: E402
from test_export_files import write_episode  # noqa: E402
from test_gui_widgets import FakeClient  # noqa: E402

NAMES = ['episode_20240101-120000', 'episode_20240102-090000', 'episode_20240102-090000_2',
         'episode_20240101-235959']


class EpisodesClient(FakeClient):
    """A FakeClient whose recorder last wrote into `directory`; it counts stop_replay()."""

    def __init__(self, directory):
        super().__init__()
        self.dir = str(directory)
        self.status = recording.Status(False, os.path.join(self.dir, NAMES[0] + '.bag'), 3.0,
                                       10, 5, '')
        self.stops = 0

    def recording_status(self):
        return self.status

    def episodes_dir(self):
        return '/nonexistent/default/episodes'

    def stop_replay(self):
        self.stops += 1


@pytest.fixture
def episodes(tmp_path):
    """Four episodes (two valid bags, two that are not bags) and a recording still running."""
    for name in NAMES[:2]:
        write_episode(tmp_path, name)
    for name in NAMES[2:]:
        (tmp_path / (name + '.bag')).write_text('not a bag')
    (tmp_path / 'episode_20240103-000000.bag.active').write_text('')
    meta = {'sides': ['L', 'R'], 'duration_s': 12.34, 'notes': 'pick up the cup'}
    (tmp_path / (NAMES[2] + '.yaml')).write_text(yaml.safe_dump(meta))
    return tmp_path


@pytest.fixture
def win(qtbot, episodes):
    window = Window(EpisodesClient(episodes), debug_mode=False)
    qtbot.addWidget(window)
    window.show()
    window.frame()
    window.opened = []
    box = window.main_tab.recording_box.replay
    box._open_file = window.opened.append
    return window


def test_episodes_are_listed_newest_first_from_the_recorders_directory(win, episodes):
    box = win.main_tab.recording_box.replay
    assert [box.episodes.itemData(i).name for i in range(box.episodes.count())] == [
        NAMES[2], NAMES[1], NAMES[3], NAMES[0]]
    assert box.episodes.itemText(0) == NAMES[2] + '  12.3 s, LR: pick up the cup'
    assert box.episodes.itemText(1) == NAMES[1] + '  1.0 s, R'
    write_episode(episodes, 'episode_20240104-080000')
    win.frame()
    assert box.episodes.count() == 4            # nothing new from the recorder: no rescan
    win.client.status = win.client.status._replace(
        episode=str(episodes / 'episode_20240104-080000.bag'))
    win.frame()
    assert box.episode().name == NAMES[2]       # the choice stays; the new one comes first
    assert box.episodes.itemData(0).name == 'episode_20240104-080000'
    win.client.status = None                    # no recorder: the default directory
    win.frame()
    assert box.episodes.itemText(0) == 'no episodes in /nonexistent/default/episodes'
    assert not box.play_button.isEnabled() and not box.plot_button.isEnabled()


def test_play_runs_the_replay_command_and_shows_its_exit_in_words(qtbot, win, episodes):
    box = win.main_tab.recording_box.replay
    box.episodes.setCurrentIndex(0)             # not a bag: the command fails reading it
    box.target.setCurrentIndex(box.target.findData(rc.INTO_PUPPET))
    box.speed.setValue(0.5)
    box.play_button.click()
    assert box.process.program() == 'rosrun'
    assert box.process.arguments() == ['robopuppet', 'replay', str(episodes / (NAMES[2] + '.bag')),
                                       '--into', 'puppet', '--side', 'R', '--speed', '0.5']
    assert box.stop_button.isEnabled() and not box.play_button.isEnabled()
    assert not box.episodes.isEnabled()
    qtbot.waitUntil(lambda: not box.running(), timeout=20000)
    text = box.state_label.text()
    assert text.startswith('failed: ') and 'cannot read the bag' in text
    assert text.endswith('(exit 2: refused or failed)')
    assert box.play_button.isEnabled() and box.episodes.isEnabled()


def test_onto_baxter_button_1_of_the_episodes_sides_and_this_puppet_stops_it(win, episodes):
    box = win.main_tab.recording_box.replay
    episode = box.episode()
    assert rc.replay_arguments(episode, rc.ONTO_ROBOT, 'R', 1.0) == [
        episode.bag, '--into', 'robot', '--side', 'LR', '--speed', '1']
    assert rc.replay_arguments(episode._replace(sides=('L',)), rc.ONTO_ROBOT, 'R', 2.0)[4] == 'LR'
    assert rc.replay_arguments(episode._replace(sides=()), rc.ONTO_ROBOT, 'R', 2.0)[4] == 'R'


@pytest.fixture
def no_master(monkeypatch):
    """The replay's node finds no ROS master (a closed port): it waits there until ended; the
    replay control waits 0.5 s (not seconds) before it ends one."""
    monkeypatch.setenv('ROS_MASTER_URI', 'http://127.0.0.1:9')
    monkeypatch.setattr(replay_box, 'STOP_GRACE_S', 0.5)
    monkeypatch.setattr(replay_box, 'CLOSE_WAIT_S', 0.5)


def test_stop_asks_the_replay_to_stop_and_ends_one_that_does_not(qtbot, win, no_master):
    box = win.main_tab.recording_box.replay
    box.episodes.setCurrentIndex(1)             # valid: the command reads it, then waits
    box.play_button.click()
    qtbot.waitUntil(lambda: box.state_label.text() == 'reading the episode', timeout=20000)
    pid = box.process.processId()
    box.stop_button.click()
    assert win.client.stops == 1 and box.state_label.text() == 'stopping'
    qtbot.waitUntil(lambda: 'terminating' in box.state_label.text(), timeout=3000)
    qtbot.waitUntil(lambda: not box.running(), timeout=10000)
    assert not alive(pid)
    text = box.state_label.text()
    assert text.startswith('ended by a signal') or text.startswith('exit 1'), text


def test_closing_the_window_stops_a_running_replay(qtbot, win, no_master):
    box = win.main_tab.recording_box.replay
    box.episodes.setCurrentIndex(1)
    box.play_button.click()
    qtbot.waitUntil(lambda: box.process.processId() > 0, timeout=5000)
    pid = box.process.processId()
    win.close()
    assert win.client.stops == 1 and not box.running() and not alive(pid)


def alive(pid):
    """Return True while a process (not yet reaped or still running) has this id."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    with open('/proc/%d/stat' % pid) as stat:
        return stat.read().split(')')[-1].split()[0] != 'Z'


def test_plot_opens_the_episodes_plot_and_makes_it_first_when_missing(qtbot, win, episodes):
    box = win.main_tab.recording_box.replay
    box.episodes.setCurrentIndex(1)
    png = episodes / (NAMES[1] + '.png')
    assert not png.exists()
    box.plot_button.click()
    assert box.plot_button.text() == 'making the plot…' and not box.plot_button.isEnabled()
    qtbot.waitUntil(lambda: bool(win.opened), timeout=60000)
    assert win.opened == [str(png)] and png.stat().st_size > 10000
    box.plot_button.click()                     # there now: opened at once
    assert win.opened == [str(png)] * 2 and box.exporter is None


@pytest.mark.parametrize('line, state', [
    ('replay: reading /e/episode_1.bag', 'reading the episode'),
    ('replay: moving slowly to the start pose of right', 'approaching the start pose'),
    ('replay: playing 1.0 of 3.0 s', 'playing 1.0 of 3.0 s'),
    ('replay: stopped: stop requested; puppet arm R holds where it is',
     'stopped: stop requested; puppet arm R holds where it is'),
    ('replay: finished', 'finished'),
    ('replay: refused: Baxter is not enabled', 'refused: Baxter is not enabled'),
    ('[WARN] [1.0]: something else', None),
    ('replay: something new', None),
])
def test_the_state_comes_from_the_commands_words(line, state):
    assert rc.state_from_line(line) == state


@pytest.mark.parametrize('code, state, shown', [
    (0, 'finished: puppet arm R holds the last recorded pose',
     'finished: puppet arm R holds the last recorded pose (exit 0: finished)'),
    (1, 'stopped: button 1 pressed', 'stopped: button 1 pressed (exit 1: stopped by a stop rule)'),
    (1, 'playing 2.0 of 3.0 s', 'exit 1: stopped by a stop rule'),
    (2, 'refused: the puppet is silent', 'refused: the puppet is silent (exit 2: refused or '
                                         'failed)'),
    (None, 'stopping', 'ended by a signal (stopping)'),
    (None, 'stopped: stop requested', 'stopped: stop requested (then ended by a signal)'),
    (7, '', 'exit 7: exit code 7'),
])
def test_exit_codes_are_shown_in_words(code, state, shown):
    assert rc.exit_text(code, state) == shown


def test_plot_shows_the_png_in_the_gui_without_a_desktop_viewer(qtbot, episodes):
    from PyQt5 import QtGui  # pylint: disable=import-outside-toplevel
    image = QtGui.QImage(1600, 1200, QtGui.QImage.Format_RGB32)
    image.fill(QtGui.QColor('white'))
    painter = QtGui.QPainter(image)
    painter.setPen(QtGui.QPen(QtGui.QColor('blue'), 6))
    painter.drawLine(0, 1200, 1600, 0)
    painter.end()
    png = episodes / (NAMES[1] + '.png')
    assert image.save(str(png))
    box = replay_box.ReplayBox(EpisodesClient(episodes))     # the default: shown in the GUI
    qtbot.addWidget(box)
    box.rescan()
    box.episodes.setCurrentIndex(1)
    box.plot_button.click()
    dialog = box.plot_dialog
    assert dialog is not None and dialog.isVisible()
    assert (dialog.pixmap.width(), dialog.pixmap.height()) == (1600, 1200)
    assert dialog.image.pixmap().size() == dialog.pixmap.size()
    assert NAMES[1] + '.png' in dialog.windowTitle()
    assert dialog.width() <= 1200 and dialog.scroll.horizontalScrollBar().maximum() > 0
    shots = os.environ.get('GUI_SHOTS')
    if shots:
        dialog.grab().save(os.path.join(shots, 'plot_dialog.png'))
    (episodes / (NAMES[0] + '.png')).write_text('not a png')
    box.episodes.setCurrentIndex(3)
    box.plot_button.click()
    assert box.state_label.text().startswith('no plot: cannot read the plot')
