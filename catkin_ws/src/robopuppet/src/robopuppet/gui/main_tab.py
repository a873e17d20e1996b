"""The main tab: heartbeat, opmode, joint and gripper table, buttons, teleop state, the link to
the robot room, serial link, recording."""
import math

from PyQt5 import QtCore, QtGui, QtWidgets

from robopuppet import interface, settings
from robopuppet.gui import link_view, state
from robopuppet.gui.link_box import LinkBox
from robopuppet.gui.recording_box import RecordingBox

LINK_STALE_S = link_view.SERIAL_STALE_S  # diagnostics older than this are shown as not updating

GREEN, AMBER, RED, GREY, BLUE = '#c8e6c9', '#ffe0b2', '#ffcdd2', '#e0e0e0', '#bbdefb'
STATUS_COLOUR = dict(zip(interface.ENC_STATUS, (GREEN, RED, AMBER)))
LINK_LEVEL = {0: ('OK', GREEN), 1: ('WARN', AMBER), 2: ('ERROR', RED), 3: ('STALE', GREY)}
TELEOP_COLOUR = {interface.CALIBRATING: AMBER, interface.READY: BLUE, interface.FOLLOWING: GREEN,
                 interface.FAULT: RED}
GRIPPER_NAMES = ('gripper 0', 'gripper 1', 'gripper 2', 'end piece')


def number(value, digits=3):
    """Return value with fixed digits, or '—' when it is unknown (NaN)."""
    return '—' if value is None or math.isnan(value) else '%+.*f' % (digits, value)


def paint(widget, colour):
    """Give a label a coloured background."""
    widget.setStyleSheet('QLabel { background: %s; padding: 3px; border-radius: 3px; }' % colour)


class MainTab(QtWidgets.QWidget):
    """Show one arm's state; the opmode buttons publish through `client.set_opmode`."""

    def __init__(self, client, parent=None):
        super().__init__(parent)
        self._client = client
        self.heartbeat_label = QtWidgets.QLabel()
        self.link_label = QtWidgets.QLabel()
        self.link_label.setWordWrap(True)
        self.teleop_label = QtWidgets.QLabel()
        self.follow_label = QtWidgets.QLabel()
        self.detail_label = QtWidgets.QLabel()
        self.detail_label.setWordWrap(True)
        self.button_label = QtWidgets.QLabel()
        self.limp_radio = QtWidgets.QRadioButton(interface.LIMP)
        self.hold_radio = QtWidgets.QRadioButton(interface.HOLD)
        self.limp_radio.clicked.connect(lambda: client.set_opmode(interface.LIMP))
        self.hold_radio.clicked.connect(lambda: client.set_opmode(interface.HOLD))
        self.joint_table = self._table(['encoder', 'angle (rad)', 'voltage (V)'],
                                       ['joint %d' % j for j in settings.JOINTS])
        self.gripper_table = self._table(['reading (0-1)'], GRIPPER_NAMES)
        end_piece_note = QtWidgets.QLabel('end piece button: ~1 released, ~0 pressed')

        top = QtWidgets.QHBoxLayout()
        top.addWidget(self._group('Puppet', self.heartbeat_label, self.button_label))
        opmode = QtWidgets.QHBoxLayout()
        opmode.addWidget(self.limp_radio)
        opmode.addWidget(self.hold_radio)
        top.addWidget(self._group('Opmode', opmode))
        top.addWidget(self._group('Teleoperation', self.teleop_label, self.follow_label,
                                  self.detail_label), 2)
        self.link_box = LinkBox()
        top.addWidget(self.link_box, 2)
        tables = QtWidgets.QHBoxLayout()
        tables.addWidget(self._group('Joints', self.joint_table), 3)
        tables.addWidget(self._group('Grippers', self.gripper_table, end_piece_note), 2,
                         QtCore.Qt.AlignTop)
        layout = QtWidgets.QVBoxLayout(self)
        layout.addLayout(top)
        layout.addLayout(tables)
        layout.addWidget(self._group('Serial link (/diagnostics)', self.link_label))
        self.recording_box = RecordingBox(client)
        layout.addWidget(self.recording_box)
        layout.addStretch(1)

    @staticmethod
    def _table(columns, rows):
        table = QtWidgets.QTableWidget(len(rows), len(columns))
        table.setHorizontalHeaderLabels(columns)
        table.setVerticalHeaderLabels(rows)
        table.setEditTriggers(QtWidgets.QAbstractItemView.NoEditTriggers)
        table.setSelectionMode(QtWidgets.QAbstractItemView.NoSelection)
        table.horizontalHeader().setSectionResizeMode(QtWidgets.QHeaderView.Stretch)
        for row in range(len(rows)):
            for column in range(len(columns)):
                table.setItem(row, column, QtWidgets.QTableWidgetItem('—'))
        table.resizeRowsToContents()
        height = table.horizontalHeader().height() + 2 * table.frameWidth()
        table.setFixedHeight(height + sum(table.rowHeight(r) for r in range(len(rows))))
        table.setVerticalScrollBarPolicy(QtCore.Qt.ScrollBarAlwaysOff)
        return table

    @staticmethod
    def _group(title, *items):
        box = QtWidgets.QGroupBox(title)
        layout = QtWidgets.QVBoxLayout(box)
        for item in items:
            if isinstance(item, QtWidgets.QLayout):
                layout.addLayout(item)
            else:
                layout.addWidget(item)
        return box

    def refresh(self, snap, now_s):
        """Show a state.Snapshot taken at now_s (s)."""
        age = state.heartbeat_age(snap, now_s)
        if age is None:
            self.heartbeat_label.setText('no heartbeat yet')
        else:
            self.heartbeat_label.setText('last heartbeat %.1f s ago' % age)
        stale = age is None or age > interface.HEARTBEAT_TIMEOUT_S
        paint(self.heartbeat_label, RED if stale else GREEN)
        self.button_label.setText('button held: %s   last pressed: %s' % (
            '—' if snap.button is None else (snap.button or 'none'), snap.last_button or 'none'))
        for radio, opmode in ((self.limp_radio, interface.LIMP),
                              (self.hold_radio, interface.HOLD)):
            if not radio.isDown():
                radio.setAutoExclusive(False)  # lets both show unchecked while opmode is unknown
                radio.setChecked(snap.opmode == opmode)
                radio.setAutoExclusive(True)
        for row, joint in enumerate(snap.joints):
            status = self.joint_table.item(row, 0)
            status.setText(joint.status or '—')
            status.setBackground(QtGui.QColor(STATUS_COLOUR.get(joint.status, GREY)))
            self.joint_table.item(row, 1).setText(number(joint.angle_rad))
            self.joint_table.item(row, 2).setText(number(joint.voltage_v, 2))
        for row, reading in enumerate(snap.grippers):
            self.gripper_table.item(row, 0).setText(number(reading))
        self._show_teleop(snap.teleop)
        self._show_link(snap.link, now_s)
        self.link_box.refresh(snap, now_s)
        self.recording_box.refresh()

    def _show_teleop(self, teleop):
        if teleop is None:
            self.teleop_label.setText('no arm controller')
            paint(self.teleop_label, GREY)
            self.follow_label.setText('')
            self.detail_label.setText('')
            return
        self.teleop_label.setText('state: %s   (opmode %s)' % (teleop.state, teleop.opmode))
        paint(self.teleop_label, TELEOP_COLOUR.get(teleop.state, GREY))
        following = [arm for arm, on in zip(interface.BAXTER_SIDES,
                                            (teleop.follow_left, teleop.follow_right)) if on]
        self.follow_label.setText('Baxter arms following: %s' % (' + '.join(following) or 'none'))
        self.detail_label.setText(teleop.detail)

    def _show_link(self, link, now_s):
        if link is None:
            self.link_label.setText('no serial link diagnostics for %s'
                                    % interface.puppet_ns(self._client.side))
            paint(self.link_label, GREY)
            return
        level, colour = LINK_LEVEL.get(link.level, ('level %d' % link.level, GREY))
        old = now_s - link.received_s
        text = '%s  %s: %s' % (level, link.name, link.message)
        if old > LINK_STALE_S:
            text += '   (no update for %.0f s)' % old
            colour = GREY
        if link.values:
            text += '\n' + '   '.join('%s: %s' % kv for kv in link.values)
        self.link_label.setText(text)
        paint(self.link_label, colour)
