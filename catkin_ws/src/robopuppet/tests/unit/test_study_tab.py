"""pytest-qt tests of the study tab: it shows the runner's StudyState, refuses a bad participant
id before sending, opens the questionnaire once per device; and its ROS client (faked)."""
import os
import threading
import types

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402
from geometry_msgs.msg import Point, Pose  # noqa: E402

from robopuppet import interface  # noqa: E402
from robopuppet.gui import look, study_tab  # noqa: E402
from robopuppet.gui.puppet_client import ConfigUnavailable  # noqa: E402
from robopuppet.gui.study_topics import StartAnswer, StudyTopics, study_of  # noqa: E402
from robopuppet.gui.window import Window  # noqa: E402
from robopuppet_msgs.msg import StudyState  # noqa: E402
from test_gui_widgets import FakeClient  # noqa: E402

RESULTS = '/home/lab/.ros/robopuppet/studies/pilot/trials.csv'


def state(phase, device='keyboard', **fields):
    """Return a StudyState as the runner publishes it during a trial of `device`."""
    msg = StudyState(phase=phase, participant='P03', device=device, task='pick_place',
                     practice=False, trial=7, trials=24, seed=4107, elapsed=12.34,
                     results=RESULTS, detail='trial 7 of 24: reach spot A with the gripper open')
    msg.targets = [Pose(position=Point(0.71, -0.32, 0.05))]
    msg.target_arms, msg.target_closed, msg.target_tolerance = ['right'], [False], [0.03]
    for name, value in fields.items():
        setattr(msg, name, value)
    return msg


class FakeStudy:
    """Stands in for StudyTopics: a runner state to show; records the calls and the answers."""

    def __init__(self, client):
        self.client = client
        self.study = None
        self.calls = []
        self.sent = []
        self.answer = StartAnswer(True, '', RESULTS)
        self.release = threading.Event()
        self.release.set()

    def now(self):
        return self.client.time_s

    def report(self, msg, age_s=0.0):
        self.study = study_of(msg, self.client.time_s - age_s)

    def study_state(self):
        return self.study

    def start_study(self, start, participant=''):
        self.calls.append((start, participant, threading.current_thread().name))
        self.release.wait(5.0)
        if self.answer is None:
            raise ConfigUnavailable('/puppet/study/start: no service')
        return self.answer

    def send_questionnaire(self, participant, device, tlx, sus):
        self.sent.append((participant, device, list(tlx), list(sus)))


@pytest.fixture
def win(qtbot):
    client = FakeClient()
    window = Window(client, debug_mode=False, study=FakeStudy(client))
    qtbot.addWidget(window)
    window.show()
    window.study = window.study_tab._study
    return window


def texts(tab):
    return {name: label.text() for name, label in tab.labels.items()}


def test_the_phases_are_the_messages():
    assert (study_tab.IDLE, study_tab.DEVICE, study_tab.TRIAL, study_tab.QUESTIONNAIRE,
            study_tab.DONE, study_tab.STOPPED) == (
        StudyState.IDLE, StudyState.DEVICE, StudyState.TRIAL, StudyState.QUESTIONNAIRE,
        StudyState.DONE, StudyState.STOPPED)


def test_the_study_tab_shows_first_and_a_trials_fields(win):
    tab = win.study_tab
    assert win.tabs.currentWidget() is tab and win.tabs.tabText(1) == 'Study'
    win.frame()
    assert tab.labels['phase'].text() == 'no study runner'
    win.study.report(state(StudyState.TRIAL))
    win.frame()
    assert texts(tab) == {
        'phase': 'study: trial', 'participant': 'P03', 'device': 'keyboard',
        'task': 'pick_place', 'trial': 'trial 7 of 24', 'elapsed': 'elapsed 12.3 s (seed 4107)',
        'goals': 'right gripper to x +0.71  y -0.32  z +0.05 m (within 3 cm), open',
        'detail': 'trial 7 of 24: reach spot A with the gripper open', 'results': RESULTS}
    assert look.GREEN in tab.labels['phase'].styleSheet()
    assert tab.stop_button.isEnabled() and not tab.start_button.isEnabled()
    win.study.report(state(StudyState.TRIAL, practice=True, trial=1, elapsed=0.5))
    win.frame()
    assert tab.labels['trial'].text() == 'trial 1 of 24 (practice)'
    assert tab.labels['elapsed'].text() == 'elapsed 0.5 s (seed 4107)'


def test_an_old_state_is_not_current_and_lets_both_buttons_act(win):
    tab = win.study_tab
    win.study.report(state(StudyState.TRIAL), age_s=study_tab.STUDY_STALE_S + 0.5)
    win.frame()
    assert tab.labels['phase'].text() == 'study: trial   NOT CURRENT'
    assert look.GREY in tab.labels['phase'].styleSheet()
    assert tab.age_label.text().startswith('NOT CURRENT: study runner last heard')
    assert tab.start_button.isEnabled() and tab.stop_button.isEnabled()


@pytest.mark.parametrize('typed, why', [
    ('', 'enter the participant id first'), ('P 01', "bad participant id 'P 01'"),
    ('P01;rm', "bad participant id 'P01;rm'"), ('Ä1', "bad participant id 'Ä1'")])
def test_start_with_a_bad_id_is_refused_before_sending(win, typed, why):
    tab = win.study_tab
    win.frame()
    tab.participant.setText(typed)
    tab.start_button.click()
    assert win.study.calls == []
    assert tab.message_label.text().startswith(why)
    assert tab.message_label.styleSheet() == study_tab.RED_TEXT


def test_start_and_stop_call_the_runner_off_the_gui_thread(qtbot, win):
    tab, study = win.study_tab, win.study
    study.report(state(StudyState.IDLE))
    win.frame()
    study.release.clear()   # a slow runner: the window keeps drawing
    tab.participant.setText(' P03 ')
    tab.start_button.click()
    win.frame()
    assert tab.busy() and not tab.start_button.isEnabled() and not tab.stop_button.isEnabled()
    study.release.set()
    qtbot.waitUntil(lambda: not tab.busy(), timeout=3000)
    assert study.calls[0][:2] == (True, 'P03')
    assert study.calls[0][2] != threading.current_thread().name
    assert tab.message_label.text() == 'results go to %s' % RESULTS
    study.report(state(StudyState.DEVICE))
    win.frame()
    study.answer = StartAnswer(False, 'no study runs', '')
    tab.stop_button.click()
    qtbot.waitUntil(lambda: not tab.busy(), timeout=3000)
    assert study.calls[1][:2] == (False, '')
    assert tab.message_label.text() == 'the study runner refused: no study runs'


def test_a_missing_runner_is_said(qtbot, win):
    tab = win.study_tab
    win.study.answer = None
    tab.participant.setText('P03')
    tab.start_button.click()
    qtbot.waitUntil(lambda: not tab.busy(), timeout=3000)
    assert tab.message_label.text() == (
        'the study runner refused: /puppet/study/start: no service')
    win.frame()
    assert tab.start_button.isEnabled()


def answer_all(dialog):
    for group in dialog.answer_groups:
        group.button(4).click()


def test_the_questionnaire_opens_once_per_device_on_any_tab(win):
    tab, study = win.study_tab, win.study
    win.tabs.setCurrentWidget(win.main_tab)   # the experimenter looks at the arm meanwhile
    study.report(state(StudyState.TRIAL))
    win.frame()
    assert tab.dialog is None
    study.report(state(StudyState.QUESTIONNAIRE))
    win.frame()
    first = tab.dialog
    assert first is not None and first.isVisible() and first.device == 'keyboard'
    first.reject()   # "Later"
    for _ in range(3):
        win.frame()
    assert tab.dialog is first and not first.isVisible()   # not forced on again
    win.tabs.setCurrentWidget(tab)
    win.frame()
    assert tab.questionnaire_button.isEnabled()
    tab.questionnaire_button.click()   # ... but the button opens it again
    assert tab.dialog is not first and tab.dialog.isVisible()
    answer_all(tab.dialog)
    tab.dialog.submit_button.click()
    assert study.sent == [('P03', 'keyboard', [50.0] * 6, [4] * 10)]
    win.frame()
    assert not tab.dialog.isVisible()
    study.report(state(StudyState.TRIAL, device='gamepad'))
    win.frame()
    assert not tab.questionnaire_button.isEnabled()
    study.report(state(StudyState.QUESTIONNAIRE, device='gamepad'))
    win.frame()
    assert tab.dialog.isVisible() and tab.dialog.device == 'gamepad'
    assert tab.dialog.windowTitle() == 'Questionnaire: gamepad, participant P03'


def test_an_old_questionnaire_state_opens_nothing(win):
    win.study.report(state(StudyState.QUESTIONNAIRE), age_s=study_tab.STUDY_STALE_S + 1.0)
    win.frame()
    assert win.study_tab.dialog is None


def test_without_study_there_is_no_study_tab(qtbot):
    window = Window(FakeClient(), debug_mode=False)
    qtbot.addWidget(window)
    assert window.study_tab is None and window.tabs.tabText(1) == 'Calibration'


def test_the_client_keeps_the_state_and_publishes_the_answers():
    fake = types.SimpleNamespace(_lock=threading.Lock(), _study=None, _clock=lambda: 7.0)
    StudyTopics._on_state(fake, state(StudyState.TRIAL))
    study = StudyTopics.study_state(fake)
    assert study.goals == (('right', (0.71, -0.32, 0.05), False, pytest.approx(0.03)),)
    assert (study.phase, study.trial, study.trials, study.received_s) == ('trial', 7, 24, 7.0)
    sent = []
    fake = types.SimpleNamespace(_answers_pub=types.SimpleNamespace(publish=sent.append),
                                 _clock=lambda: 8.5)
    StudyTopics.send_questionnaire(fake, 'P03', 'marker', [10, 20, 30, 40, 50, 60], (5,) * 10)
    assert (sent[0].participant, sent[0].device) == ('P03', 'marker')
    assert sent[0].tlx == [10.0, 20.0, 30.0, 40.0, 50.0, 60.0] and sent[0].sus == [5] * 10
    assert sent[0].header.stamp.to_sec() == 8.5
    assert interface.STUDY_QUESTIONNAIRE == '/puppet/study/questionnaire'


def test_the_client_asks_the_runner_and_names_a_missing_one():
    requests = []

    class Proxy:
        up = True

        def wait_for_service(self, timeout_s):
            if not self.up:
                raise __import__('rospy').ROSException('timeout exceeded')

        def __call__(self, *args):
            requests.append(args)
            return types.SimpleNamespace(ok=True, error='', results=RESULTS)

    fake = types.SimpleNamespace(_start=Proxy())
    assert StudyTopics.start_study(fake, True, 'P03') == StartAnswer(True, '', RESULTS)
    assert requests == [(True, 'P03', [], [])]
    fake._start.up = False
    with pytest.raises(ConfigUnavailable, match='/puppet/study/start: timeout exceeded'):
        StudyTopics.start_study(fake, False)
