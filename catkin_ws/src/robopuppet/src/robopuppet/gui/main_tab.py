"""The main tab: the puppet (heartbeat, opmode, buttons, serial link), the teleop state, the link
to the robot room, the assist, joint and gripper tables and, beside them, the camera; recording."""
import math

from PyQt5 import QtCore, QtGui, QtWidgets

from robopuppet import interface, settings
from robopuppet.gui import assist_box, camera_view, freshness, link_view, state, tracking
from robopuppet.gui.link_box import LinkBox
from robopuppet.gui.look import (AMBER, BLUE, GREEN, GREY, RED, grey_out, number, paint, restyle,
                                 show_age)
from robopuppet.gui.recording_box import RecordingBox

LINK_STALE_S = link_view.SERIAL_STALE_S  # diagnostics older than this are shown as not updating

STATUS_COLOUR = dict(zip(interface.ENC_STATUS, (GREEN, RED, AMBER)))
LINK_LEVEL = {link_view.OK: ('OK', GREEN), link_view.WARN: ('WARN', AMBER),
              link_view.ERROR: ('ERROR', RED), 3: ('STALE', GREY)}
TELEOP_COLOUR = {interface.CALIBRATING: AMBER, interface.READY: BLUE, interface.FOLLOWING: GREEN,
                 interface.FAULT: RED}
GRIPPER_NAMES = ('gripper 0', 'gripper 1', 'gripper 2', 'end piece')
ERROR_COLOUR = {tracking.SMALL: GREEN, tracking.MEDIUM: AMBER, tracking.LARGE: RED}
LINE_COLOUR = {tracking.ZONE: AMBER, tracking.LAGS: RED, tracking.TRACKS: GREEN,
               tracking.IDLE: GREY}
BAXTER_COLUMN, ERROR_COLUMN = 3, 4
CAMERA_SHARE = 0.35  # of the width at first, for the camera; the splitter moves it


def baxter_header(arm, mirrored):
    """Return the Baxter column's header: two lines, so that it fits the column."""
    return 'Baxter (rad)\n%s' % ('%s, mirrored' % arm if mirrored else '%s arm' % arm)


class MainTab(QtWidgets.QWidget):
    """Show one arm's state; the opmode buttons publish through `client.set_opmode`.

    The joint table shows, beside the puppet's angles, Baxter's measured angles of the arm this
    puppet drives mapped into puppet space and the error puppet - Baxter (gui.tracking); the
    line under it names the keep-out zone holding Baxter back, or says Baxter lags.

    What comes from the robot room (the arm controller's state, Baxter's pose, the link) shows
    its age; once no longer current (gui.freshness) it is greyed and says NOT CURRENT.

    With a camera_pane (CameraPane), the camera shows to the right of the status (a splitter):
    the hand camera of the Baxter arm the puppet drives until the operator chooses another.
    The pane subscribes only while the tab is visible.
    """

    def __init__(self, client, camera_pane=None, parent=None):
        super().__init__(parent)
        self._client = client
        self.camera_pane = camera_pane
        self.heartbeat_label = QtWidgets.QLabel()
        self.link_label = QtWidgets.QLabel()
        self.link_label.setWordWrap(True)
        self.teleop_label = QtWidgets.QLabel()
        self.follow_label = QtWidgets.QLabel()
        self.detail_label = QtWidgets.QLabel()
        self.detail_label.setWordWrap(True)
        self.teleop_age_label = QtWidgets.QLabel()
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
        self.baxter_age_label = QtWidgets.QLabel()
        # wrapped, so that the status column can make room for the camera
        for label in (self.heartbeat_label, self.button_label, self.teleop_label,
                      self.follow_label, self.teleop_age_label, self.baxter_age_label):
            label.setWordWrap(True)
        self._lag = {side: tracking.LagWatch() for side in interface.BAXTER_SIDES}
        self.gripper_table = self._table(['reading (0-1)'], GRIPPER_NAMES)
        end_piece_note = QtWidgets.QLabel('end piece button: ~1 released, ~0 pressed')
        end_piece_note.setWordWrap(True)

        top = QtWidgets.QHBoxLayout()
        opmode = QtWidgets.QHBoxLayout()
        for radio, _ in self.opmode_radios:
            opmode.addWidget(radio)
        opmode.addStretch(1)   # a radio takes clicks on its mark and text only: keep it narrow
        # The puppet's own state in one box, its serial link (/diagnostics) last: the status
        # column stays short enough for the whole joint table beside the camera.
        puppet = self._group('Puppet', self.heartbeat_label, opmode, self.button_label,
                             self.link_label)
        puppet.layout().addStretch(1)
        top.addWidget(puppet, 2)
        top.addWidget(self._group('Teleoperation', self.teleop_label, self.follow_label,
                                  self.detail_label, self.teleop_age_label), 2)
        self.link_box = LinkBox()
        self.assist_box = assist_box.AssistBox(client)   # hidden until the assist reports
        top.addWidget(self.link_box, 2)
        tables = QtWidgets.QHBoxLayout()
        tables.addWidget(self._group('Joints', self.joint_table, self.tracking_label,
                                     self.baxter_age_label), 3)
        grippers = self._group('Grippers', self.gripper_table, end_piece_note)
        if camera_pane is None:
            tables.addWidget(grippers, 2, QtCore.Qt.AlignTop)
        layout = QtWidgets.QVBoxLayout(self)
        status = QtWidgets.QVBoxLayout()
        for item in (top, self.assist_box, tables) if camera_pane is None else (top, tables):
            (status.addLayout if isinstance(item, QtWidgets.QLayout) else status.addWidget)(item)
        if camera_pane is None:
            layout.addLayout(status)
        else:  # the assist, the camera and the grippers to the right: the joints keep their room
            self.splitter = QtWidgets.QSplitter()
            for items in (((status, 0),),
                          ((self.assist_box, 0), (camera_pane, 1), (grippers, 0))):
                self.splitter.addWidget(QtWidgets.QWidget())
                column = QtWidgets.QVBoxLayout(self.splitter.widget(self.splitter.count() - 1))
                column.setContentsMargins(0, 0, 0, 0)
                for item, stretch in items:   # the camera takes the height left over
                    (column.addLayout if isinstance(item, QtWidgets.QLayout)
                     else column.addWidget)(item, stretch)
            status.addStretch(1)
            self.splitter.setChildrenCollapsible(False)
            self.splitter.setStretchFactor(0, 1)
            self.splitter.setStretchFactor(1, 1)
            camera_pane.prefer(camera_view.own_camera(interface.BAXTER_SIDE[client.side]))
            layout.addWidget(self.splitter, 1)
        self.recording_box = RecordingBox(client)
        layout.addWidget(self.recording_box)
        if camera_pane is None:
            layout.addStretch(1)

    def showEvent(self, event):
        """Give the camera CAMERA_SHARE of the width when first shown (laid out by then)."""
        super().showEvent(event)
        if self.camera_pane is not None and not getattr(self, '_split', False):
            self._split = True
            QtCore.QTimer.singleShot(0, lambda: self.splitter.setSizes(
                [int(self.splitter.width() * (1 - CAMERA_SHARE)),
                 int(self.splitter.width() * CAMERA_SHARE)]))

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
        # the header's size hint: the two-line Baxter header is taller than one not yet laid out
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
        self._show_teleop(snap.teleop, now_s)
        self._show_link(snap.link, now_s)
        self.link_box.refresh(snap, now_s)
        self.assist_box.refresh(now_s)
        self.recording_box.refresh()
        if self.camera_pane is not None:
            teleop = snap.teleop
            follows = (teleop.follow_left, teleop.follow_right) if teleop else (False, False)
            self.camera_pane.prefer(camera_view.own_camera(
                tracking.driven_arm(self._client.side, *follows)))
            self.camera_pane.refresh(snap, now_s)

    def _show_teleop(self, teleop, now_s):
        received_s = None if teleop is None else teleop.received_s
        what = 'arm_%s' % self._client.side
        stale = show_age(self.teleop_age_label, received_s, now_s, freshness.TELEOP_STALE_S,
                         what)
        for label in (self.follow_label, self.detail_label):
            grey_out(label, stale)
        if teleop is None:
            self.teleop_label.setText('no arm controller')
            paint(self.teleop_label, GREY)
            self.follow_label.setText('')
            self.detail_label.setText('')
            return
        self.teleop_label.setText('state: %s   (opmode %s)%s' % (
            teleop.state, teleop.opmode, '   NOT CURRENT' if stale else ''))
        paint(self.teleop_label, GREY if stale else TELEOP_COLOUR.get(teleop.state, GREY))
        following = [arm for arm, on in zip(interface.BAXTER_SIDES,
                                            (teleop.follow_left, teleop.follow_right)) if on]
        self.follow_label.setText('Baxter arms following: %s' % (' + '.join(following) or 'none'))
        self.detail_label.setText(teleop.detail)

    def _show_tracking(self, snap, now_s):
        """Fill the Baxter and error columns and the zone or lag line."""
        side, teleop = self._client.side, snap.teleop
        follows = (teleop.follow_left, teleop.follow_right) if teleop else (False, False)
        teleop_stale = teleop is not None and freshness.is_stale(
            teleop.received_s, now_s, freshness.TELEOP_STALE_S)
        received_s = None if snap.baxter is None else snap.baxter.received_s
        baxter_stale = show_age(self.baxter_age_label, received_s, now_s,
                                freshness.BAXTER_STALE_S, "Baxter's pose")
        poses = {} if baxter_stale else snap.baxter.poses
        puppet = [joint.angle_rad for joint in snap.joints]
        arm = tracking.driven_arm(side, *follows)
        track = tracking.tracking(side, arm, poses, puppet)
        # An old pose is shown greyed, without errors: an error against it would mislead.
        old = tracking.tracking(side, arm, snap.baxter.poses, puppet) if (
            baxter_stale and snap.baxter is not None) else None
        # Colour judges the error where it matters: an arm that follows, or feel mode (the
        # puppet pulls toward the shown arm); an arm that does not follow is elsewhere by design.
        judged = not teleop_stale and (follows[interface.BAXTER_SIDES.index(arm)]
                                       or snap.opmode == interface.FEEL)
        header = baxter_header(arm, arm != interface.BAXTER_SIDE[side])
        if self.joint_table.horizontalHeaderItem(BAXTER_COLUMN).text() != header:
            self.joint_table.horizontalHeaderItem(BAXTER_COLUMN).setText(header)
        for row in range(settings.NUM_JOINTS):
            shown = track or old
            baxter = math.nan if shown is None else shown.baxter_rad[row]
            error = math.nan if track is None else track.error_rad[row]
            for column, value in ((BAXTER_COLUMN, baxter), (ERROR_COLUMN, error)):
                cell = self.joint_table.item(row, column)
                cell.setText(number(value))
                cell.setForeground(QtGui.QColor(freshness.STALE_TEXT_COLOUR) if baxter_stale
                                   else QtGui.QBrush())
            self.joint_table.item(row, BAXTER_COLUMN).setBackground(
                QtGui.QColor(GREY) if baxter_stale else QtGui.QBrush())
            level = tracking.error_level(error) if judged else None
            cell.setBackground(QtGui.QColor(ERROR_COLOUR[level]) if level else QtGui.QBrush())
        lagging = {}
        for follower, following in zip(interface.BAXTER_SIDES, follows):
            worst = None
            if following and follower in poses and not teleop_stale:
                worst = tracking.largest_error(tracking.tracking(side, follower, poses, puppet))
            large = worst is not None and tracking.error_level(worst[1]) == tracking.LARGE
            if self._lag[follower].update(now_s, large):
                lagging[follower] = worst
        line = tracking.status_line(
            teleop, lagging, bool(poses),
            freshness.age_s(teleop.received_s, now_s) if teleop_stale else None,
            freshness.age_s(received_s, now_s))
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
        # Every key value in the tooltip; on the (narrow) box only when not OK: what went wrong.
        self.link_label.setToolTip('\n'.join('%s: %s' % kv for kv in link.values))
        if link.values and link.level != link_view.OK:
            text += '\n' + '   '.join('%s: %s' % kv for kv in link.values)
        self.link_label.setText(text)
        paint(self.link_label, colour)

