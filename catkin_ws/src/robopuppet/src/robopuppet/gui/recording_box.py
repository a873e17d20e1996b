"""The Recording box: start and stop a demonstration episode, with its task and notes; the
recorder's status; below it the replay control (robopuppet.gui.replay_box)."""
from PyQt5 import QtWidgets

from robopuppet.episodes import recording
from robopuppet.gui.config_task import ConfigTask
from robopuppet.gui.replay_box import ReplayBox

RECORD_TIMEOUT_S = 5.0   # the recorder answers at once; a busy machine may take longer
RED_TEXT = 'QLabel { color: #c62828; font-weight: bold; }'


class RecordingBox(QtWidgets.QGroupBox):
    """Start/Stop (the recorder's /puppet/record, off the GUI thread), the task and notes, live
    status; the replay control (`replay`, a ReplayBox). The task stays for the next episode
    (a nurse records the same task many times); the recorder checks it.

    Args:
        client: a PuppetClient (or a test double) with record(start, notes, task) and
            recording_status(), and what ReplayBox needs.
    """

    def __init__(self, client, parent=None):
        super().__init__('Recording and replay: button 4 starts and stops recording',
                         parent)
        self._client = client
        self._call = ConfigTask(self)
        self._refusal = ''
        self.button = QtWidgets.QPushButton('Start recording')
        self.button.clicked.connect(self.toggle)
        self.task = QtWidgets.QLineEdit()
        self.task.setPlaceholderText('task, e.g. pick up the cup')
        self.task.setToolTip('What the episodes demonstrate, for language-conditioned policies '
                             "(kept for the next episode; empty: the recorder's task parameter)")
        self.task.setMaxLength(recording.TASK_MAX_CHARS)
        self.notes = QtWidgets.QLineEdit()
        self.notes.setPlaceholderText('notes (optional)')
        self.status_label = QtWidgets.QLabel(recording.status_text(None))
        self.status_label.setWordWrap(True)
        self.replay = ReplayBox(client)
        row = QtWidgets.QHBoxLayout()
        row.addWidget(self.button)
        row.addWidget(self.task, 3)
        row.addWidget(self.notes, 2)
        rows = QtWidgets.QVBoxLayout(self)
        rows.addLayout(row)
        rows.addWidget(self.status_label)  # the whole width: a refusal in one or two lines
        rows.addWidget(self.replay)

    def busy(self):
        """Return True while a Record call has not answered."""
        return self._call.busy()

    def toggle(self):
        """Ask the recorder to stop the running episode, or to start one with the task and notes."""
        if self._call.busy():
            return
        status = self._client.recording_status()
        start = not (status is not None and status.recording)
        notes, task = self.notes.text(), self.task.text()
        self.button.setEnabled(False)
        self._call.start(lambda: self._client.record(start, notes, task), self._answered,
                         RECORD_TIMEOUT_S)

    def _answered(self, answer, error):
        self.button.setEnabled(True)
        if error is None and not answer.ok:
            error = answer.error
        self._refusal = error or ''

    def refresh(self):
        """Show the recorder's latest status (call once per frame, on the GUI thread)."""
        status = self._client.recording_status()
        recording_now = status is not None and status.recording
        self.button.setText('Stop recording' if recording_now else 'Start recording')
        text = recording.status_text(status)
        if self._refusal and not recording_now:
            text = self._refusal
        elif recording_now:
            self._refusal = ''
        self.status_label.setText(text)
        red = recording_now or bool(self._refusal) or bool(status and status.problem)
        self.status_label.setStyleSheet(RED_TEXT if red else '')
        self.replay.refresh()
