"""The main tab: heartbeat, opmode, joint and gripper table, buttons, teleop state, the link to
the robot room, serial link, recording."""
import math

from PyQt5 import QtCore, QtGui, QtWidgets

from robopuppet import interface, settings
from robopuppet.gui import link_view, state, tracking
from robopuppet.gui.link_box import LinkBox
from robopuppet.gui.recording_box import RecordingBox

LINK_STALE_S = link_view.SERIAL_STALE_S  # diagnostics older than this are shown as not updating

GREEN, AMBER, RED, GREY, BLUE = '#c8e6c9', '#ffe0b2', '#ffcdd2', '#e0e0e0', '#bbdefb'
STATUS_COLOUR = dict(zip(interface.ENC_STATUS, (GREEN, RED, AMBER)))
LINK_LEVEL = {0: ('OK', GREEN), 1: ('WARN', AMBER), 2: ('ERROR', RED), 3: ('STALE', GREY)}
TELEOP_COLOUR = {interface.CALIBRATING: AMBER, interface.READY: BLUE, interface.FOLLOWING: GREEN,
                 interface.FAULT: RED}
GRIPPER_NAMES = ('gripper 0', 'gripper 1', 'gripper 2', 'end piece')
ERROR_COLOUR = {tracking.SMALL: GREEN, tracking.MEDIUM: AMBER, tracking.LARGE: RED}
LINE_COLOUR = {tracking.ZONE: AMBER, tracking.LAGS: RED, tracking.TRACKS: GREEN,
               tracking.IDLE: GREY}
BAXTER_COLUMN, ERROR_COLUMN = 3, 4


def number(value, digits=3):
    """Return value with fixed digits, or '—' when it is unknown (NaN)."""
    return '—' if value is None or math.isnan(value) else '%+.*f' % (digits, value)


def baxter_header(arm, mirrored):
    """Return the Baxter column's header: two lines, so that it fits the column."""
    return 'Baxter (rad)\n%s' % ('%s, mirrored' % arm if mirrored else '%s arm' % arm)


def paint(widget, colour):
    """Give a label a coloured background."""
    widget.setStyleSheet('QLabel { background: %s; padding: 3px; border-radius: 3px; }' % colour)


class MainTab(QtWidgets.QWidget):
    """Show one arm's state; the opmode buttons publish through `client.set_opmode`.

    The joint table shows, beside the puppet's angles, Baxter's measured angles of the arm this
    puppet drives mapped into puppet space and the error puppet - Baxter (gui.tracking); the
    line under it names the keep-out zone holding Baxter back, or says Baxter lags.
    """

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
        self.feel_radio = QtWidgets.QRadioButton(interface.FEEL)
        self.feel_radio.setToolTip("hold with gentle gains, set to Baxter's pose: the puppet "
                                   'pulls back where Baxter cannot follow')
        self.opmode_radios = ((self.limp_radio, interface.LIMP), (self.hold_radio, interface.HOLD),
                              (self.feel_radio, interface.FEEL))
        for radio, mode in self.opmode_radios:
            radio.clicked.connect(lambda _=False, mode=mode: client.set_opmode(mode))
        self.joint_table = self._table(['encoder', 'angle (rad)', 'voltage (V)',
                                        baxter_header('right', False), 'error (rad)'],
                                       ['joint %d' % j for j in settings.JOINTS])
        self.tracking_label = QtWidgets.QLabel()
        self.tracking_label.setWordWrap(True)
        self._lag = {side: tracking.LagWatch() for side in interface.BAXTER_SIDES}
        self.gripper_table = self._table(['reading (0-1)'], GRIPPER_NAMES)
        end_piece_note = QtWidgets.QLabel('end piece button: ~1 released, ~0 pressed')

        top = QtWidgets.QHBoxLayout()
        top.addWidget(self._group('Puppet', self.heartbeat_label, self.button_label))
        opmode = QtWidgets.QHBoxLayout()
        for radio, _ in self.opmode_radios:
            opmode.addWidget(radio)
        top.addWidget(self._group('Opmode', opmode))
        top.addWidget(self._group('Teleoperation', self.teleop_label, self.follow_label,
                                  self.detail_label), 2)
        self.link_box = LinkBox()
        top.addWidget(self.link_box, 2)
        tables = QtWidgets.QHBoxLayout()
        tables.addWidget(self._group('Joints', self.joint_table, self.tracking_label), 3)
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
        # the header's size hint, not its height: the two-line Baxter header is taller than a
        # header not yet laid out
        height = table.horizontalHeader().sizeHint().height() + 2 * table.frameWidth()
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
        for radio, opmode in self.opmode_radios:
            if not radio.isDown():
                radio.setAutoExclusive(False)  # lets all show unchecked while opmode is unknown
                radio.setChecked(snap.opmode == opmode)
                radio.setAutoExclusive(True)
        for row, joint in enumerate(snap.joints):
            status = self.joint_table.item(row, 0)
            status.setText(joint.status or '—')
            status.setBackground(QtGui.QColor(STATUS_COLOUR.get(joint.status, GREY)))
            self.joint_table.item(row, 1).setText(number(joint.angle_rad))
            self.joint_table.item(row, 2).setText(number(joint.voltage_v, 2))
        self._show_tracking(snap, now_s)
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

    def _show_tracking(self, snap, now_s):
        """Fill the Baxter and error columns and the zone or lag line."""
        side, teleop = self._client.side, snap.teleop
        follows = (teleop.follow_left, teleop.follow_right) if teleop else (False, False)
        poses = {}
        if snap.baxter is not None and now_s - snap.baxter.received_s <= tracking.BAXTER_STALE_S:
            poses = snap.baxter.poses
        puppet = [joint.angle_rad for joint in snap.joints]
        arm = tracking.driven_arm(side, *follows)
        track = tracking.tracking(side, arm, poses, puppet)
        # Colour judges the error where it matters: an arm that follows, or feel mode (the
        # puppet pulls toward the shown arm); an arm that does not follow is elsewhere by design.
        judged = follows[interface.BAXTER_SIDES.index(arm)] or snap.opmode == interface.FEEL
        header = baxter_header(arm, arm != interface.BAXTER_SIDE[side])
        if self.joint_table.horizontalHeaderItem(BAXTER_COLUMN).text() != header:
            self.joint_table.horizontalHeaderItem(BAXTER_COLUMN).setText(header)
        for row in range(settings.NUM_JOINTS):
            baxter = math.nan if track is None else track.baxter_rad[row]
            error = math.nan if track is None else track.error_rad[row]
            self.joint_table.item(row, BAXTER_COLUMN).setText(number(baxter))
            cell = self.joint_table.item(row, ERROR_COLUMN)
            cell.setText(number(error))
            level = tracking.error_level(error) if judged else None
            cell.setBackground(QtGui.QColor(ERROR_COLOUR[level]) if level else QtGui.QBrush())
        lagging = {}
        for follower, following in zip(interface.BAXTER_SIDES, follows):
            worst = None
            if following and follower in poses:
                worst = tracking.largest_error(tracking.tracking(side, follower, poses, puppet))
            large = worst is not None and tracking.error_level(worst[1]) == tracking.LARGE
            if self._lag[follower].update(now_s, large):
                lagging[follower] = worst
        line = tracking.status_line(teleop, lagging, bool(poses))
        self.tracking_label.setText(line.text)
        paint(self.tracking_label, LINE_COLOUR[line.level])

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
