"""The study tab (gui_X with ~study true): the participant id, Start/Stop of the study runner,
what it does now (phase, device, task, trial n of N, elapsed, the goals and its detail, the
results file) and, after each device, the questionnaire (gui.questionnaire_dialog).

describe() decides what shows (pure); StudyTab only draws it and makes the calls.
"""
import collections

from PyQt5 import QtWidgets

from robopuppet.gui import freshness
from robopuppet.gui.config_task import ConfigTask
from robopuppet.gui.look import AMBER, BLUE, GREEN, GREY, RED, paint, show_age
from robopuppet.gui.questionnaire_dialog import QuestionnaireDialog
from robopuppet.study import results

# The runner publishes its state on every change and at least every 0.5 s: three missed.
STUDY_STALE_S = 1.5
START_TIMEOUT_S = 5.0   # the runner answers at once; a busy machine may take longer
# robopuppet_msgs/StudyState's phases (this module imports no message package; a test holds
# them to the message's constants).
IDLE, DEVICE, TRIAL, QUESTIONNAIRE, DONE, STOPPED = (
    'idle', 'device', 'trial', 'questionnaire', 'done', 'stopped')
PHASE_COLOUR = {IDLE: GREY, DEVICE: BLUE, TRIAL: GREEN, QUESTIONNAIRE: AMBER, DONE: GREEN,
                STOPPED: RED}
RUNNING = (DEVICE, TRIAL, QUESTIONNAIRE)
RED_TEXT = 'QLabel { color: #c62828; font-weight: bold; }'

View = collections.namedtuple('View', 'phase colour participant device task trial elapsed goals '
                                      'detail results can_start can_stop stale')
View.__doc__ = """What the tab shows: the phase line and its colour, the participant, device,
task, trial and elapsed lines, the goals (one line each), the detail, the results file, whether
Start and Stop are enabled, and whether the state is not current."""


def check_participant(participant):
    """Return '' when participant is a valid id for StudyStart (the runner's rule,
    study.results), else why not."""
    if not participant:
        return 'enter the participant id first (e.g. P01)'
    try:
        results.check_participant(participant)
    except results.ResultsError as error:
        return str(error)
    return ''


def goal_line(goal):
    """Return one goal (arm, (x, y, z) m, closed, tolerance m) as the tab shows it."""
    arm, (x, y, z), closed, tolerance_m = goal
    return '%s gripper to x %+.2f  y %+.2f  z %+.2f m (within %.0f cm), %s' % (
        arm, x, y, z, tolerance_m * 100, 'closed' if closed else 'open')


def describe(study, now_s):
    """Return the View of a study_topics.Study (None: nothing heard yet) at now_s (s)."""
    if study is None:
        return View('no study runner', GREY, '', '', '', '', '', (), '', '', True, False, True)
    stale = freshness.is_stale(study.received_s, now_s, STUDY_STALE_S)
    running = study.phase in RUNNING
    trial = ''
    if study.trials:
        trial = 'trial %d of %d%s' % (study.trial, study.trials,
                                      ' (practice)' if study.practice else '')
    timed = study.phase == TRIAL
    return View('study: %s%s' % (study.phase, '   NOT CURRENT' if stale else ''),
                GREY if stale else PHASE_COLOUR.get(study.phase, GREY),
                study.participant, study.device, study.task if timed else '', trial,
                'elapsed %.1f s (seed %d)' % (study.elapsed_s, study.seed) if timed else '',
                tuple(goal_line(g) for g in study.goals) if timed else (), study.detail,
                study.results, not running or stale, running or stale, stale)


class StudyTab(QtWidgets.QWidget):
    """Run a study from the GUI and answer its questionnaires.

    Args:
        study: a StudyTopics (or a test double) with now(), study_state(),
            start_study(start, participant) and send_questionnaire(participant, device, tlx,
            sus).
    refresh(snap, now_s) once per frame while the tab shows; watch(now_s) while it does not
    (the questionnaire opens whichever tab shows: once per study, participant and device).
    """

    def __init__(self, study, parent=None):
        super().__init__(parent)
        self._study = study
        self._call = ConfigTask(self)
        self._asked = set()    # (results, participant, device) whose questionnaire opened
        self.dialog = None
        self.participant = QtWidgets.QLineEdit()
        self.participant.setPlaceholderText('participant id, e.g. P01')
        self.participant.setMaxLength(40)
        self.participant.returnPressed.connect(self.start)
        self.start_button = QtWidgets.QPushButton('Start study')
        self.stop_button = QtWidgets.QPushButton('Stop study')
        self.questionnaire_button = QtWidgets.QPushButton('Questionnaire…')
        self.start_button.clicked.connect(self.start)
        self.stop_button.clicked.connect(self.stop)
        self.questionnaire_button.clicked.connect(self.ask)
        self.message_label = QtWidgets.QLabel()
        self.message_label.setWordWrap(True)
        row = QtWidgets.QHBoxLayout()
        row.addWidget(QtWidgets.QLabel('Participant'))
        for widget, stretch in ((self.participant, 1), (self.start_button, 0),
                                (self.stop_button, 0), (self.questionnaire_button, 0)):
            row.addWidget(widget, stretch)
        self.labels = {name: QtWidgets.QLabel() for name in View._fields[:10]
                       if name != 'colour'}
        form = QtWidgets.QFormLayout()
        for name in ('phase', 'participant', 'device', 'task', 'trial', 'elapsed', 'goals',
                     'detail', 'results'):
            self.labels[name].setWordWrap(True)
            form.addRow(name, self.labels[name])
        self.age_label = QtWidgets.QLabel()
        box = QtWidgets.QGroupBox('Study')
        inner = QtWidgets.QVBoxLayout(box)
        inner.addLayout(form)
        inner.addWidget(self.age_label)
        layout = QtWidgets.QVBoxLayout(self)
        layout.addLayout(row)
        layout.addWidget(self.message_label)
        layout.addWidget(box)
        layout.addStretch(1)
        self.view = None

    def busy(self):
        """Return True while a StudyStart call has not answered."""
        return self._call.busy()

    def start(self):
        """Ask the runner to start a study for the entered participant; a bad id is refused
        here, with a message, and nothing is sent."""
        participant = self.participant.text().strip()
        why = check_participant(participant)
        if why:
            self._say(why, True)
            return
        self._request(True, participant)

    def stop(self):
        """Ask the runner to stop the running study."""
        self._request(False, '')

    def _request(self, start, participant):
        if self._call.busy():
            return
        self.start_button.setEnabled(False)
        self.stop_button.setEnabled(False)
        self._say('starting the study for %s…' % participant if start else 'stopping…', False)
        self._call.start(lambda: self._study.start_study(start, participant),
                         self._answered, START_TIMEOUT_S)

    def _answered(self, answer, error):
        if error is None and not answer.ok:
            error = answer.error
        if error:
            self._say('the study runner refused: %s' % error, True)
        else:
            self._say('results go to %s' % answer.results if answer.results else '', False)
        self.view = None   # enable the buttons by the state again

    def _say(self, text, refusal):
        self.message_label.setText(text)
        self.message_label.setStyleSheet(RED_TEXT if refusal else '')

    def ask(self):
        """Open the questionnaire of the current device (phase QUESTIONNAIRE) unless it shows."""
        study = self._study.study_state()
        if study is None or study.phase != QUESTIONNAIRE:
            return
        self._asked.add((study.results, study.participant, study.device))
        if self.dialog is not None and self.dialog.isVisible():
            if (self.dialog.participant, self.dialog.device) == (study.participant,
                                                                 study.device):
                return
            self.dialog.reject()
        self.dialog = QuestionnaireDialog(study.participant, study.device, self._submit, self)
        self.dialog.open()

    def _submit(self, participant, device, tlx, sus):
        self._study.send_questionnaire(participant, device, tlx, sus)
        self._say('answers about the %s sent for %s' % (device, participant), False)

    def watch(self, now_s):
        """Open the questionnaire once when the runner asks for it (on the GUI thread)."""
        study = self._study.study_state()
        if (study is not None and study.phase == QUESTIONNAIRE
                and not freshness.is_stale(study.received_s, now_s, STUDY_STALE_S)
                and (study.results, study.participant, study.device) not in self._asked):
            self.ask()
        return study

    def refresh(self, snap, now_s):
        """Show the runner's latest state as of now_s (s); snap (the arm's) is not used."""
        study = self.watch(now_s)
        show_age(self.age_label, None if study is None else study.received_s, now_s,
                 STUDY_STALE_S, 'study runner')
        view = describe(study, now_s)
        self.questionnaire_button.setEnabled(
            study is not None and study.phase == QUESTIONNAIRE)
        if view == self.view:
            return   # unchanged: no relayout at 30 frames/s
        self.view = view
        for name, label in self.labels.items():
            value = getattr(view, name)
            label.setText('\n'.join(value) if name == 'goals' else value)
        paint(self.labels['phase'], view.colour)
        self.start_button.setEnabled(view.can_start and not self.busy())
        self.stop_button.setEnabled(view.can_stop and not self.busy())
