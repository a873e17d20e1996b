"""A joint tab: live angle and voltage plots, the twelve settings with Get/Set, a setpoint."""
import functools

from PyQt5 import QtCore, QtWidgets

from robopuppet import settings
from robopuppet.gui import settings_form
from robopuppet.gui.config_task import ConfigTask
from robopuppet.gui.live_plot import LivePlot
from robopuppet.gui.look import number

NOW_LABEL_WIDTH = 420  # pixels
CALL_TIMEOUT_S = 2.0  # a get_config or set_config call (1 s to find the service, then the call)
OK_STYLE = 'QLabel { color: #1b5e20; }'
ERROR_STYLE = 'QLabel { color: #b71c1c; font-weight: bold; }'
FIELD_ERROR_STYLE = 'QLineEdit { border: 2px solid #c62828; background: #ffebee; }'
FIELD_PROBLEM_STYLE = 'QLabel { color: #b71c1c; }'
FIELD_COLUMN_WIDTH = 260  # pixels: a field's problem wraps under it within this width


class JointTab(QtWidgets.QWidget):
    """Plots and settings of one joint; talks to the arm through a PuppetClient-like `client`.

    The client needs get_config(joint) and set_config(joint, {name: value}) (blocking, raising
    ConfigUnavailable; only ever called on a worker thread; set_config returns a
    puppet_client.SetAnswer), set_setpoint(joint, angle_rad) and side.
    """

    def __init__(self, client, joint, window_s=10.0, parent=None):
        super().__init__(parent)
        self._client = client
        self.joint = joint
        self.stored = None  # the joint's settings as the config node last reported them
        self._filled = None  # {name: value} the fields were filled with; edits are against it
        self._read_once = False
        self._task = ConfigTask(self)
        self.angle_plot = LivePlot('joint %d angle' % joint, 'rad',
                                   [('angle', '#1565c0', False), ('setpoint', '#ef6c00', True)],
                                   window_s)
        self.voltage_plot = LivePlot('joint %d motor voltage' % joint, 'V',
                                     [('voltage', '#c62828', False)], window_s)
        self.fields = {}
        self.field_problems = {}  # setting name: the label under its field naming its problems
        self._tips = {}
        form = QtWidgets.QFormLayout()
        for setting in settings.SETTINGS:
            field = QtWidgets.QLineEdit()
            self._tips[setting.name] = '%s (default %s)' % (
                setting.meaning, settings_form.field_text(setting.default))
            field.setToolTip(self._tips[setting.name])
            field.setMaximumWidth(120)
            field.textEdited.connect(lambda _, name=setting.name: self._mark_field(name, []))
            problem = QtWidgets.QLabel()
            problem.setWordWrap(True)
            problem.setStyleSheet(FIELD_PROBLEM_STYLE)
            problem.setFixedWidth(FIELD_COLUMN_WIDTH)
            problem.hide()
            column = QtWidgets.QVBoxLayout()
            column.setSpacing(1)
            column.addWidget(field)
            column.addWidget(problem)
            self.fields[setting.name] = field
            self.field_problems[setting.name] = problem
            form.addRow('%s (%s)' % (setting.name, setting.unit), column)
        self.get_button = QtWidgets.QPushButton('Get')
        self.get_button.setToolTip('read the stored settings from config_%s' % client.side)
        self.set_button = QtWidgets.QPushButton('Set')
        self.set_button.setToolTip('send the settings edited since Get to config_%s (stored '
                                   'all or none, then sent to the puppet)' % client.side)
        self.get_button.clicked.connect(self.get)
        self.set_button.clicked.connect(self.set)
        buttons = QtWidgets.QHBoxLayout()
        buttons.addWidget(self.get_button)
        buttons.addWidget(self.set_button)
        form.addRow(buttons)
        self.message = QtWidgets.QLabel()
        self.message.setWordWrap(True)
        self.message.setMinimumWidth(240)
        self.message.setSizePolicy(QtWidgets.QSizePolicy.Preferred,
                                   QtWidgets.QSizePolicy.MinimumExpanding)
        form.addRow(self.message)
        self.setpoint_field = QtWidgets.QLineEdit()
        self.setpoint_field.setMaximumWidth(120)
        self.setpoint_button = QtWidgets.QPushButton('Send setpoint')
        self.setpoint_button.clicked.connect(self.send_setpoint)
        self.setpoint_field.returnPressed.connect(self.send_setpoint)
        setpoint = QtWidgets.QHBoxLayout()
        setpoint.addWidget(self.setpoint_field)
        setpoint.addWidget(self.setpoint_button)
        form.addRow('setpoint (rad, hold)', setpoint)
        box = QtWidgets.QGroupBox('Settings of joint %d' % joint)
        box.setLayout(form)
        self.now_label = QtWidgets.QLabel()
        # A fixed size keeps the text changing every frame from re-laying out the whole tab.
        self.now_label.setFixedSize(NOW_LABEL_WIDTH, self.now_label.sizeHint().height())
        plots = QtWidgets.QVBoxLayout()
        plots.addWidget(self.now_label)
        plots.addWidget(self.angle_plot)
        plots.addWidget(self.voltage_plot)
        layout = QtWidgets.QHBoxLayout(self)
        layout.addLayout(plots, 1)
        layout.addWidget(box, 0, QtCore.Qt.AlignTop)

    def extend(self, points):
        """Append drained ArmState points {(series, joint): [(t, v)]} of this joint."""
        for series, plot in (('angle', self.angle_plot), ('setpoint', self.angle_plot),
                             ('voltage', self.voltage_plot)):
            new = points.get((series, self.joint))
            if new:
                plot.extend(series, new)

    def refresh(self, snap, now_s):
        """Show the joint's latest values (a state.Snapshot); redraw the plots, now_s at 0."""
        joint = snap.joints[self.joint]
        self.now_label.setText('now:  %s   %s rad   %s V   opmode %s' % (
            joint.status or '—', number(joint.angle_rad), number(joint.voltage_v, 2),
            snap.opmode or '—'))
        self.angle_plot.refresh(now_s)
        self.voltage_plot.refresh(now_s)

    def showEvent(self, event):
        """Read the settings the first time the tab is shown, once it has painted."""
        super().showEvent(event)
        if not self._read_once:
            self._read_once = True
            QtCore.QTimer.singleShot(0, self.get)

    def busy(self):
        """Return True while Get or Set waits for the config node."""
        return self._task.busy()

    def get(self):
        """Read the stored settings (get_config, off the GUI thread) into the fields."""
        if self.busy():
            return
        self._say('reading the stored settings of joint %d...' % self.joint)
        self._start(lambda: self._client.get_config(self.joint), self._got)

    def _got(self, stored, error):
        if error is not None:
            self._say('config node not reachable, nothing changed: %s' % error, error=True)
            return
        self.stored = stored
        self._show(stored)
        self._say('read the stored settings of joint %d' % self.joint)

    def _show(self, stored, texts=None):
        """Fill the fields with the stored {name: value}; edits are counted against these.

        With texts ({name: text} the fields held when the call started), a field typed into
        since keeps what the operator typed: an unsaved edit is never overwritten.
        """
        self._filled = dict(stored)
        self._mark_fields({})
        for name, value in stored.items():
            if texts is None or self.fields[name].text() == texts[name]:
                self.fields[name].setText(settings_form.field_text(value))

    def set(self):
        """Check the fields and send the ones edited since Get to set_config, in one request.

        Nothing is sent when any field is refused or the settings were never read. Fields the
        operator did not edit are not sent, so a change made elsewhere meanwhile is not
        reverted; the config node checks the edits against what it stores, all or none. When it
        has stored them the fields show what it stores; when it refuses, the fields keep the
        edits and the message says why.
        """
        if self.busy():
            return
        texts = {name: field.text() for name, field in self.fields.items()}
        try:
            wanted = settings_form.parse_form(self.joint, texts)
        except settings_form.EntryError as error:
            self._mark_fields(error.by_field())
            count = len(error.problems)
            self._say('refused, nothing sent: %s, marked red at %s:\n%s' % (
                '1 problem' if count == 1 else '%d problems' % count,
                'its field' if count == 1 else 'their fields', error), error=True)
            return
        self._mark_fields({})
        if self._filled is None:
            self._say('read the stored settings first (Get); nothing sent', error=True)
            return
        edited = {name: value for name, value in wanted.items() if value != self._filled[name]}
        if not edited:
            self._say('no change: no field was edited since the settings were read')
            return
        self._say('sending %s...' % describe(edited.items()))
        self._start(lambda: self._client.set_config(self.joint, edited),
                    functools.partial(self._answered_set, texts))

    def _answered_set(self, texts, answer, error):
        if error is not None:
            self._say('config node not reachable: %s; Get shows what is stored' % error,
                      error=True)
            return
        self.stored = answer.values
        if not answer.stored:
            self._say('refused by config_%s, nothing changed:\n%s'
                      % (self._client.side, answer.error), error=True)
            return
        self._show(answer.values, texts)
        self._say('saved: joint %d settings stored (the serial node sends them to the puppet)'
                  % self.joint)

    def send_setpoint(self):
        """Publish the setpoint entry (rad), refused when not a number or out of limits."""
        try:
            angle_rad = settings_form.parse_setpoint(self.setpoint_field.text(), self.stored)
        except settings_form.EntryError as error:
            self._say('refused, nothing sent: %s' % error, error=True)
            return
        self._client.set_setpoint(self.joint, angle_rad)
        self._say('setpoint %s rad sent (the puppet follows it in hold mode)'
                  % settings_form.field_text(angle_rad))

    def _start(self, work, on_done):
        """Run work() on a worker thread, Get and Set disabled until on_done(result, error):
        result None and error a text when work raised ConfigUnavailable or CALL_TIMEOUT_S
        passed."""
        self._task.start(work, functools.partial(self._answered, on_done), CALL_TIMEOUT_S)
        self._enable_buttons()

    def _answered(self, on_done, result, error):
        self._enable_buttons()
        on_done(result, error)

    def _enable_buttons(self):
        for button in (self.get_button, self.set_button):
            button.setEnabled(not self.busy())

    def _mark_fields(self, problems):
        """Mark each field of {name: [problem texts]} red with its problems; clear the others."""
        for name in self.fields:
            self._mark_field(name, problems.get(name, []))

    def _mark_field(self, name, problems):
        """Mark one field red with its problems under it and in its tooltip, or clear it."""
        field, label = self.fields[name], self.field_problems[name]
        field.setStyleSheet(FIELD_ERROR_STYLE if problems else '')
        field.setToolTip('\n'.join(problems + [self._tips[name]]))
        label.setText('\n'.join(problems))
        label.setVisible(bool(problems))

    def _say(self, text, error=False):
        self.message.setText(text)
        self.message.setStyleSheet(ERROR_STYLE if error else OK_STYLE)


def describe(changes):
    """Return 'name = value, ...' for [(name, value), ...]."""
    return ', '.join('%s = %s' % (name, settings_form.field_text(value))
                     for name, value in changes)
