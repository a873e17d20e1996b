"""The calibration wizard: each joint's home_angle and sign_angle from poses (one arm).

Steps (robopuppet.calibration.procedure): Start checks that every quadrature joint is Working
and says which to turn; then, for each pose, the figure shows it and Capture (or a press of the
end-piece button while this tab is shown) captures it; then the table shows old and new values
and each joint's residual; Apply stores them (one all-or-none set_arm_config request for every
joint, off the GUI thread); Undo stores the old values of the joints Apply wrote the same way;
Check asks for each joint to be moved in Baxter's positive direction and names the joints that
move the wrong way; Motors checks each joint's sign_motor in hold at a safe voltage
(calibration.motor_check), Stop ends it, and Flip corrects the joints whose motor pushes the
wrong way.

While a pose is awaited, a timer (procedure.TARGET_RATE_HZ, whichever tab is shown) publishes it
as the calibration target for RViz; the same timer runs the motor check. If the window closes
during the motor check, the puppet goes limp and the stored voltage limits are restored before
the window goes (when ROS is shut down already, they cannot be: they are printed on stderr).
"""
import math
import sys

from PyQt5 import QtCore, QtWidgets

from robopuppet import interface, settings
from robopuppet.calibration import motor_check, procedure, solver
from robopuppet.config import follow_lock
from robopuppet.gui.config_task import ConfigTask
from robopuppet.gui.main_tab import GREEN, RED, number, paint
from robopuppet.gui.pose_figure import PoseFigure

APPLY_TIMEOUT_S = 10.0  # one set_arm_config call: up to 1 s for the service, then the write
COLUMNS = ('target', 'reported', 'home old', 'home new', 'sign old', 'sign new', 'residual',
           'problem')


class CalibrationTab(QtWidgets.QWidget):
    """The wizard for one arm. `client`: a PuppetClient (or a double with .state, .now(),
    .stored_settings(), .set_arm_config(values), .publish_target(pose), .set_opmode(opmode)
    and .set_setpoint(joint, angle_rad))."""

    def __init__(self, client, parent=None):
        super().__init__(parent)
        self.client = client
        self.session = None
        self.changes = None  # [procedure.Change] once every pose is captured
        self.undo_values = {}  # {joint: old values} of the joints the last Apply wrote
        self.check = None  # a procedure.DirectionCheck while checking
        self.motors = None  # the latest motor_check.MotorCheck
        self.step = 'idle'  # idle, encoders, pose, review, check, motors
        self._press = procedure.EndPiecePress()
        self._task = ConfigTask(self)
        self._readings = [(None, math.nan)] * settings.NUM_JOINTS
        self._following = ''  # follow_lock.following() of the newest teleop_state ('' none)
        self.instruction = QtWidgets.QLabel('Press Start to calibrate the home angles and signs.')
        self.instruction.setWordWrap(True)
        self.instruction.setStyleSheet('font-size: 15px; font-weight: bold;')
        self.figure = PoseFigure()
        self.table = QtWidgets.QTableWidget(settings.NUM_JOINTS, len(COLUMNS))
        self.table.setHorizontalHeaderLabels(COLUMNS)
        self.table.setVerticalHeaderLabels(['joint %d' % j for j in settings.JOINTS])
        self.table.horizontalHeader().setStretchLastSection(True)
        self.message = QtWidgets.QLabel('')
        self.message.setWordWrap(True)
        buttons = QtWidgets.QHBoxLayout()
        self.buttons = {}
        for name, slot in (('Start', self.start), ('Capture', self.capture),
                           ('Retake', self.retake), ('Apply', self.apply), ('Undo', self.undo),
                           ('Check', self.start_check), ('Motors', self.start_motors),
                           ('Stop', self.stop_motors), ('Flip', self.flip)):
            button = QtWidgets.QPushButton(name)
            button.clicked.connect(slot)
            buttons.addWidget(button)
            self.buttons[name] = button
        layout = QtWidgets.QVBoxLayout(self)
        layout.addWidget(self.instruction)
        layout.addWidget(self.figure)
        layout.addLayout(buttons)
        layout.addWidget(self.table, 1)
        layout.addWidget(self.message)
        self._timer = QtCore.QTimer(self)
        self._timer.timeout.connect(self._tick)
        self._timer.start(int(1000.0 / procedure.TARGET_RATE_HZ))
        QtWidgets.QApplication.instance().aboutToQuit.connect(self._on_quit)
        self._enable()

    # Steps ----------------------------------------------------------------------------------
    def start(self):
        """Begin a new run: forget the captures; the encoders step comes first."""
        if self.step == 'motors':
            return
        self.session, self.changes, self.check = procedure.Session(), None, None
        self.step = 'encoders'
        self._say('')
        self._advance()

    def capture(self):
        """Capture the pose shown from the latest readings and the stored settings."""
        if self.step != 'pose':
            return
        try:
            self.session.capture(self._readings, self.client.stored_settings())
        except procedure.CaptureError as error:
            self._say(str(error), error=True)
            return
        self._say('captured %d of %d' % (len(self.session.raws), len(self.session.poses)))
        self._advance()

    def retake(self):
        """Go back one pose (after the last one too, to capture it again)."""
        if self.step in ('pose', 'review') and self.session.raws:
            self.session.retake()
            self.changes, self.step = None, 'pose'
            self._advance()

    def apply(self):
        """Store the new values, all joints in one request, off the GUI thread."""
        if self.step != 'review' or self._task.busy():
            return
        if self._following:
            self._say('not applied: %s' % self._following, error=True)
            return
        old = {c.joint: c.old for c in self.changes}
        new = {c.joint: c.new for c in self.changes}
        self._say('storing the new values…')
        self._task.start(lambda: procedure.apply_changes(self.client.set_arm_config, new),
                         lambda applied, error: self._applied(applied, error, 'new', old),
                         APPLY_TIMEOUT_S)
        self._enable()

    def undo(self):
        """Store the old values of the joints the last Apply wrote, in one step."""
        if not self.undo_values or self._task.busy() or self.step == 'motors':
            return
        old = dict(self.undo_values)
        self._say('restoring the old values…')
        self._task.start(lambda: procedure.apply_changes(self.client.set_arm_config, old),
                         lambda applied, error: self._applied(applied, error, 'old', None),
                         APPLY_TIMEOUT_S)
        self._enable()

    def start_check(self):
        """Ask for each joint in turn to be moved in Baxter's positive direction."""
        if self.step == 'motors':
            return
        self.check, self.step = procedure.DirectionCheck(), 'check'
        self._say('')
        self._advance()

    def start_motors(self):
        """Check each joint's sign_motor in hold, limited to motor_check.SAFE_VOLTAGE_V."""
        stored = self.client.stored_settings()
        if self._task.busy() or self.step not in ('idle', 'review') or stored is None:
            return
        self.motors, self.step = motor_check.MotorCheck(stored), 'motors'
        self._say('')
        self.client.set_opmode(interface.LIMP)
        self._do(self.motors.start())

    def stop_motors(self):
        """Stop the motor check: limp now, then restore the stored voltage limits."""
        if self.step == 'motors' and self.motors.phase not in ('restore', 'done'):
            self._do(self.motors.cancel())

    def flip(self):
        """Store the flipped sign_motor of the joints the motor check found wrong."""
        if self.motors is None or not self.motors.wrong() or self._task.busy():
            return
        wrong = self.motors.wrong()
        old = {j: {'sign_motor': self.motors.signs[j]} for j in wrong}
        self._say('flipping sign_motor of joints %s…' % wrong)
        self._task.start(lambda: procedure.apply_changes(self.client.set_arm_config,
                                                         self.motors.flips(wrong)),
                         lambda applied, error: self._applied(applied, error, 'flipped', old),
                         APPLY_TIMEOUT_S)
        self.motors = None
        self._enable()

    def _tick(self):
        """Publish the awaited pose as the target; run the motor check between stores."""
        if self.step == 'pose' and self.session.pose() is not None:
            self.client.publish_target(self.session.pose())
        if self.step == 'motors' and not self._task.busy():
            joints = self.client.state.snapshot().joints
            self._do(self.motors.update(self.client.now(), [j.angle_rad for j in joints],
                                        [j.voltage_v for j in joints]))

    def _do(self, command):
        """Do a motor_check.Command."""
        if command.kind in ('limp', 'hold'):
            self.client.set_opmode(command.kind)
        elif command.kind == 'setpoint':
            self.client.set_setpoint(command.joint, command.values)
        elif command.kind == 'store':
            self._task.start(
                lambda: procedure.apply_changes(self.client.set_arm_config, command.values),
                self._motors_stored, APPLY_TIMEOUT_S)
        self._show_motors()

    def _motors_stored(self, applied, error):
        problem = error or (applied.error if applied else '')
        self._do(self.motors.stored(self.client.now(), problem))

    def _show_motors(self):
        motors, joint = self.motors, self.motors.joint()
        for checked, result in motors.results.items():
            self._cell(checked, 7, 'motor: %s' % result)
        if joint is not None:
            self.instruction.setText(
                'Motors: let the arm hang down and hold it, but let joint %d move freely: in '
                'hold at %.1f V at most, its setpoint moves %+.1f rad.' % (
                    joint, motor_check.SAFE_VOLTAGE_V, motor_check.STEP_RAD))
        elif motors.phase == 'restore':
            self.instruction.setText('Motors: restoring the stored voltage limits…')
        elif motors.phase == 'done':
            self.step = 'idle'
            if 'restoring' in motors.error:  # Undo tries again
                self.undo_values = {j: dict(self.undo_values.get(j, {}), **v)
                                    for j, v in motors.restore_values().items()}
            wrong = motors.wrong()
            self.instruction.setText('Motor check done.' + (
                ' Flip stores the flipped sign_motor of joints %s.' % wrong if wrong else ''))
            self._say('%s%s' % ('STOPPED: %s. ' % motors.error if motors.error else '',
                                'sign_motor wrong on joints %s' % wrong if wrong else
                                'results: %s' % motors.results),
                      error=bool(motors.error or wrong))
        self._enable()

    def _on_quit(self):
        """The application ends: never leave the puppet in hold at the check's limits."""
        if self.motors is None or self.motors.phase == 'done':
            return
        self.client.set_opmode(interface.LIMP)
        applied = procedure.apply_changes(self.client.set_arm_config,
                                          self.motors.restore_values())
        if applied.error:
            sys.stderr.write('calibration: restoring the voltage limits failed (%s); set them '
                             'again: %s\n' % (applied.error, self.motors.restore_values()))

    def _applied(self, applied, error, which, old):
        """A store ended: old is {joint: old values} after Apply, None after Undo."""
        written = applied.written if applied else []
        if old is None:  # what Undo could not restore stays to undo
            self.undo_values = {j: v for j, v in self.undo_values.items() if j not in written}
        elif written:  # a refused store wrote nothing: the last Apply's undo stays
            self.undo_values = {j: old[j] for j in written}
            if self.step == 'review':
                self.step = 'idle'
        problem = error or (applied.error if applied else '')
        if problem:
            self._say('FAILED: %s. The %s values were not stored: every joint keeps what it '
                      'had.' % (problem, which), error=True)
        else:
            self.instruction.setText('Stored. Check tests each joint\'s direction; Undo restores '
                                     'the old values.' if self.undo_values else 'Restored.')
            self._say('stored the %s values of joints %s%s' % (
                which, written, '; Undo restores the old ones' if self.undo_values else ''))
        self._enable()

    # Frames ---------------------------------------------------------------------------------
    def refresh(self, snap, now_s):
        """Take the latest readings; the end-piece button captures while a pose is awaited."""
        self._readings = [(j.status, j.angle_rad) for j in snap.joints]
        teleop = snap.teleop
        following = follow_lock.following(teleop.follow_left, teleop.follow_right) if (
            teleop and now_s - teleop.received_s <= follow_lock.TELEOP_STALE_S) else ''
        if following != self._following:
            self._following = following
            self._enable()
        pressed = self._press.update(snap.grippers[interface.END_PIECE_GRIPPER])
        if pressed and self.step == 'pose':
            self.capture()
        if self.step == 'check' and self.check.update([a for _, a in self._readings]) is not None:
            self._advance()
        elif self.step == 'encoders':
            self._advance()
        pose = self.session.pose() if self.session and self.step == 'pose' else None
        self.figure.show_pose(pose.angles_rad if pose else [math.nan] * settings.NUM_JOINTS,
                              [a for _, a in self._readings])
        for joint, (_, angle) in enumerate(self._readings):
            self._cell(joint, 1, number(angle))

    def _advance(self):
        """Move to the step the state calls for and say what to do."""
        if self.step == 'encoders':
            turn = procedure.joints_to_turn(self._readings)
            if turn:
                self.instruction.setText('Turn joints %s through their index mark (0 rad) until '
                                         'they read Working.' % turn)
            else:
                self.step = 'pose'
        if self.step == 'pose':
            pose = self.session.pose()
            if pose is None:
                self._review()
            else:
                self.instruction.setText(
                    'Pose %d of %d, %s: pose the puppet like the blue needles, then press '
                    'Capture or the end-piece button.' % (len(self.session.raws) + 1,
                                                          len(self.session.poses), pose.name))
                for joint, angle in enumerate(pose.angles_rad):
                    self._cell(joint, 0, number(angle))
        if self.step == 'check':
            joint = self.check.joint()
            for checked, right in self.check.moved_positive.items():
                self._cell(checked, 7, 'moves the right way' if right else 'MOVES THE WRONG WAY')
            if joint is not None:
                self.instruction.setText('Check: move joint %d in Baxter\'s positive direction '
                                         '(the dial\'s counter-clockwise way).' % joint)
            else:
                wrong = self.check.wrong()
                self.instruction.setText('Check done.')
                self._say('joints %s move the wrong way: calibrate again' % wrong if wrong
                          else 'every joint moves the right way', error=bool(wrong))
                self.step = 'idle'
        self._enable()

    def _review(self):
        try:
            self.changes = self.session.changes(self.client.stored_settings())
        except (solver.SolveError, TypeError) as error:
            self._say('cannot solve: %s' % error, error=True)
            return
        self.step = 'review'
        flagged = [c.joint for c in self.changes if c.fit.problem]
        for c in self.changes:
            texts = ('%.4f' % c.old['home_angle'], '%.4f' % c.new['home_angle'],
                     '%+.0f' % c.old['sign_angle'], '%+.0f' % c.new['sign_angle'],
                     '%.4f' % c.fit.residual_rad, c.fit.problem or 'ok')
            for column, text in enumerate(texts, start=2):
                self._cell(c.joint, column, text)
        self.instruction.setText('Old and new values side by side. ' + (
            'Joints %s are flagged: Retake their poses or Start again.' % flagged if flagged
            else 'Apply stores the new values.'))

    # Widgets --------------------------------------------------------------------------------
    def _cell(self, row, column, text):
        item = self.table.item(row, column)
        if item is None:
            item = QtWidgets.QTableWidgetItem()
            self.table.setItem(row, column, item)
        item.setText(text)

    def _enable(self):
        busy = self._task.busy()
        flagged = self.changes is None or any(c.fit.problem for c in self.changes)
        self.buttons['Start'].setEnabled(not busy and self.step != 'motors')
        self.buttons['Capture'].setEnabled(self.step == 'pose')
        self.buttons['Retake'].setEnabled(self.step in ('pose', 'review') and not busy
                                          and bool(self.session and self.session.raws))
        # A new home or sign would move a following Baxter arm: config_X refuses it then too.
        meaning = any(n in settings.ANGLE_SETTINGS for v in self.undo_values.values() for n in v)
        self.buttons['Apply'].setEnabled(self.step == 'review' and not flagged and not busy
                                         and not self._following)
        self.buttons['Apply'].setToolTip(self._following)
        self.buttons['Undo'].setEnabled(bool(self.undo_values) and not busy
                                        and self.step != 'motors'
                                        and not (meaning and self._following))
        self.buttons['Undo'].setToolTip(self._following if meaning else '')
        self.buttons['Check'].setEnabled(not busy and self.step in ('idle', 'review'))
        self.buttons['Motors'].setEnabled(not busy and self.step in ('idle', 'review'))
        self.buttons['Stop'].setEnabled(self.step == 'motors')
        self.buttons['Flip'].setEnabled(not busy and self.step == 'idle' and
                                        bool(self.motors and self.motors.wrong()))

    def _say(self, text, error=False):
        self.message.setText(text)
        paint(self.message, RED if error else GREEN)
