"""A joint tab: live angle and voltage plots, the twelve settings with Get/Set, a setpoint."""
from PyQt5 import QtCore, QtWidgets

from robopuppet import settings
from robopuppet.gui import settings_form
from robopuppet.gui.live_plot import LivePlot
from robopuppet.gui.main_tab import number
from robopuppet.gui.puppet_client import ConfigUnavailable

NOW_LABEL_WIDTH = 420  # pixels
CHECK_DELAY_MS = 600  # after Set, read the settings back this much later to confirm them
OK_STYLE = 'QLabel { color: #1b5e20; }'
ERROR_STYLE = 'QLabel { color: #b71c1c; font-weight: bold; }'


class JointTab(QtWidgets.QWidget):
    """Plots and settings of one joint; talks to the arm through a PuppetClient-like `client`.

    The client needs get_config(joint) (raising ConfigUnavailable), set_setting(joint, name,
    value), set_setpoint(joint, angle_rad) and side.
    """

    def __init__(self, client, joint, window_s=10.0, parent=None):
        super().__init__(parent)
        self._client = client
        self.joint = joint
        self.stored = None  # the joint's settings as last read from get_config
        self._read_once = False
        self.angle_plot = LivePlot('joint %d angle' % joint, 'rad',
                                   [('angle', '#1565c0', False), ('setpoint', '#ef6c00', True)],
                                   window_s)
        self.voltage_plot = LivePlot('joint %d motor voltage' % joint, 'V',
                                     [('voltage', '#c62828', False)], window_s)
        self.fields = {}
        form = QtWidgets.QFormLayout()
        for setting in settings.SETTINGS:
            field = QtWidgets.QLineEdit()
            field.setToolTip('%s (default %s)' % (setting.meaning,
                                                 settings_form.field_text(setting.default)))
            field.setMaximumWidth(120)
            self.fields[setting.name] = field
            form.addRow('%s (%s)' % (setting.name, setting.unit), field)
        self.get_button = QtWidgets.QPushButton('Get')
        self.get_button.setToolTip('read the stored settings from config_%s' % client.side)
        self.set_button = QtWidgets.QPushButton('Set')
        self.set_button.setToolTip('send the changed settings (stored and sent to the puppet)')
        self.get_button.clicked.connect(self.get)
        self.set_button.clicked.connect(self.set)
        buttons = QtWidgets.QHBoxLayout()
        buttons.addWidget(self.get_button)
        buttons.addWidget(self.set_button)
        form.addRow(buttons)
        self.message = QtWidgets.QLabel()
        self.message.setWordWrap(True)
        self.message.setMinimumWidth(240)
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

    def get(self):
        """Fill the fields with the stored settings (get_config)."""
        if self._read_stored():
            for name, value in self.stored.items():
                self.fields[name].setText(settings_form.field_text(value))
            self._say('read the stored settings of joint %d' % self.joint)

    def set(self):
        """Check the fields and publish the settings that differ from the stored ones.

        Nothing is published when any field is refused or the stored settings cannot be read
        (they decide the safe order of a minimum and a maximum).
        """
        texts = {name: field.text() for name, field in self.fields.items()}
        try:
            wanted = settings_form.parse_form(self.joint, texts)
        except settings_form.EntryError as error:
            self._say('refused, nothing sent:\n%s' % error, error=True)
            return
        if not self._read_stored():
            return
        changes = settings_form.publish_order(self.stored, wanted)
        if not changes:
            self._say('no change: the fields hold the stored settings')
            return
        for name, value in changes:
            self._client.set_setting(self.joint, name, value)
        self._say('sent %s; checking...' % ', '.join(
            '%s = %s' % (name, settings_form.field_text(value)) for name, value in changes))
        QtCore.QTimer.singleShot(CHECK_DELAY_MS, lambda: self._confirm(wanted))

    def _confirm(self, wanted):
        if not self._read_stored():
            return
        differ = [name for name in settings.NAMES if self.stored[name] != wanted[name]]
        if differ:
            self._say('not stored by config_%s: %s (see its log)' % (self._client.side, ', '.join(
                '%s is %s' % (n, settings_form.field_text(self.stored[n])) for n in differ)),
                error=True)
        else:
            self._say('saved: joint %d settings stored and sent to the puppet' % self.joint)

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

    def _read_stored(self):
        try:
            self.stored = self._client.get_config(self.joint)
        except ConfigUnavailable as error:
            self._say('config node not reachable, nothing changed: %s' % error, error=True)
            return False
        return True

    def _say(self, text, error=False):
        self.message.setText(text)
        self.message.setStyleSheet(ERROR_STYLE if error else OK_STYLE)
