"""pytest-qt tests of the main tab's Recording box, with a fake recorder behind the client."""
import os
import threading

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402

from robopuppet.episodes import recording  # noqa: E402
from robopuppet.gui import recording_box  # noqa: E402
from robopuppet.gui.puppet_client import ConfigUnavailable, RecordAnswer  # noqa: E402
from robopuppet.gui.window import Window  # noqa: E402
from test_gui_widgets import FakeClient  # noqa: E402


class RecorderClient(FakeClient):
    """A FakeClient with a recorder: record() answers like /puppet/record, from a thread."""

    def __init__(self):
        super().__init__()
        self.status = recording.IDLE
        self.calls = []
        self.refusal = ''
        self.up = True
        self.release = threading.Event()
        self.release.set()

    def recording_status(self):
        return self.status

    def record(self, start, notes, task):
        self.calls.append((start, notes, task, threading.current_thread().name))
        self.release.wait(5.0)
        if not self.up:
            raise ConfigUnavailable('/puppet/record: no service')
        if self.refusal:
            return RecordAnswer(False, self.refusal, '')
        self.status = recording.Status(start, '/e/episode_1.bag', 0.0, 0, 0, '')
        return RecordAnswer(True, '', '/e/episode_1.bag')


@pytest.fixture
def win(qtbot):
    window = Window(RecorderClient(), debug_mode=False)
    qtbot.addWidget(window)
    window.show()
    return window


def test_start_sends_the_notes_off_the_gui_thread_and_stop_follows(qtbot, win):
    box, client = win.main_tab.recording_box, win.client
    client.release.clear()  # the recorder is slow to answer: the window keeps drawing
    box.notes.setText('pick up the cup')
    box.button.click()
    frames = win.frames
    win.frame()
    assert win.frames == frames + 1 and box.busy() and not box.button.isEnabled()
    client.release.set()
    qtbot.waitUntil(lambda: not box.busy(), timeout=3000)
    assert client.calls[0][:3] == (True, 'pick up the cup', '')
    assert client.calls[0][3] != threading.current_thread().name
    client.status = recording.Status(True, '/e/episode_1.bag', 12.3, 3_400_000, 99, '')
    win.frame()
    assert box.status_label.text() == 'REC 00:12, 3.4 MB'
    assert recording_box.RED_TEXT in box.status_label.styleSheet()
    assert box.button.text() == 'Stop recording'
    box.button.click()
    qtbot.waitUntil(lambda: not box.busy(), timeout=3000)
    assert client.calls[1][0] is False
    win.frame()
    assert box.button.text() == 'Start recording'
    assert box.status_label.styleSheet() == ''


@pytest.mark.parametrize('refusal, up, shown', [
    ('disk nearly full: 120 MB free, recording needs at least 200 MB', True, 'disk nearly full'),
    ('', False, 'no service'),
])
def test_a_refusal_or_a_missing_recorder_is_shown_in_red(qtbot, win, refusal, up, shown):
    box, client = win.main_tab.recording_box, win.client
    client.refusal, client.up = refusal, up
    box.button.click()
    qtbot.waitUntil(lambda: not box.busy(), timeout=3000)
    win.frame()
    assert shown in box.status_label.text() and box.button.isEnabled()
    assert recording_box.RED_TEXT in box.status_label.styleSheet()
    assert not client.status.recording


def test_the_task_goes_with_each_start_and_stays_for_the_next_episode(qtbot, win):
    box, client = win.main_tab.recording_box, win.client
    box.task.setText('pick up the cup and hand it to the patient')
    box.notes.setText('demo 1')
    for k in range(2):   # start, stop, start again: the nurse types the task once
        box.button.click()
        qtbot.waitUntil(lambda: not box.busy(), timeout=3000)
        win.frame()
    assert [call[:3] for call in client.calls] == [
        (True, 'demo 1', 'pick up the cup and hand it to the patient'),
        (False, 'demo 1', 'pick up the cup and hand it to the patient')]
    assert box.task.text() == 'pick up the cup and hand it to the patient'
    box.notes.setText('demo 2')
    box.button.click()
    qtbot.waitUntil(lambda: not box.busy(), timeout=3000)
    assert client.calls[2][:3] == (True, 'demo 2', 'pick up the cup and hand it to the patient')
    box.task.setText('x' * 600)   # the field holds no more than the recorder takes
    assert box.task.text() == 'x' * recording.TASK_MAX_CHARS


def test_a_problem_the_recorder_reports_is_shown_in_red(win):
    win.client.status = recording.Status(False, '/e/episode_1.bag', 30.0, 10, 5,
                                         'disk nearly full: 150 MB free')
    win.frame()
    box = win.main_tab.recording_box
    assert box.status_label.text() == 'disk nearly full: 150 MB free'
    assert recording_box.RED_TEXT in box.status_label.styleSheet()
