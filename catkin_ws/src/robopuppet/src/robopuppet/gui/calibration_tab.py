"""The calibration wizard: each joint's home_angle and sign_angle from poses (one arm).

Steps (calibration.procedure): Start says which quadrature joints to turn until Working; then
for each pose the figure shows it and Capture (or the end-piece button while this tab shows)
captures it; the table shows old and new values and residuals; Apply and Undo store them
(gui.calibration_store: one all-or-none request); Check names the joints that move the wrong
way; Motors checks each sign_motor in hold at a safe voltage (gui.motor_step), Stop ends it and
Flip corrects it. With the simulated puppet, "Pose the virtual puppet" sets its hand to the pose
awaited. A timer (procedure.TARGET_RATE_HZ) publishes the awaited pose as the calibration target
for RViz and runs the motor check; closing the window mid-check limps the puppet and restores
the voltage limits (printed on stderr when ROS is down already).
"""
import functools
import math

from PyQt5 import QtCore, QtWidgets

from robopuppet import interface, settings
from robopuppet.calibration import procedure, solver
from robopuppet.config import follow_lock
from robopuppet.gui import calibration_store
from robopuppet.gui.config_task import ConfigTask
from robopuppet.gui.look import GREEN, RED, number, paint
from robopuppet.gui.motor_step import MotorStep, before_text
from robopuppet.gui.pose_figure import PoseFigure

COLUMNS = ('target', 'reported', 'home old', 'home new', 'sign old', 'sign new', 'residual',
           'problem')


class CalibrationTab(QtWidgets.QWidget):
    """The wizard for one arm. `client`: a PuppetClient (or a double with .state, .now(),
    .stored_settings(), .set_arm_config(values), .publish_target(pose), .set_opmode(opmode)
    and .set_setpoint(joint, angle_rad)); `sim`: a SimPuppetClient (or a double with
    .set_hand(seven angles rad)) with the simulated puppet, else None. hand_posed(angles) is
    emitted just before "Pose the virtual puppet" publishes them (for the panel's sliders).
    """

    APPLY_TIMEOUT_S = calibration_store.APPLY_TIMEOUT_S
    hand_posed = QtCore.pyqtSignal(list)

    def __init__(self, client, sim=None, parent=None):
        super().__init__(parent)
        self.client, self.sim = client, sim
        self.session = None
        self.changes = None  # [procedure.Change] once every pose is captured
        self.undo_values = {}  # {joint: old values} of the joints the last Apply wrote
        self.check = None  # a procedure.DirectionCheck while checking
        self.step = 'idle'  # idle, encoders, pose, review, check, motors
        self._press = procedure.EndPiecePress()
        self.task = self._task = ConfigTask(self)
        self._motor_step = MotorStep(self, sim is not None)
        self._readings = [(None, math.nan)] * settings.NUM_JOINTS
        self.following = ''  # follow_lock.following() of the newest teleop_state ('' none)
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
        self.buttons['Motors'].setToolTip(before_text(0, sim is not None))
        self.pose_button = QtWidgets.QPushButton('Pose the virtual puppet')
        self.pose_button.setToolTip('set the simulated hand to the pose awaited (the puppet '
                                    'moves there at up to 3 rad/s)')
        self.pose_button.clicked.connect(self.pose_sim)
        self.pose_button.setVisible(sim is not None)
        top = QtWidgets.QHBoxLayout()
        top.addWidget(self.instruction, 1)
        top.addWidget(self.pose_button)
        tables = QtWidgets.QHBoxLayout()
        tables.addWidget(self.table, 3)
        tables.addWidget(self._motor_step.table, 1)
        layout = QtWidgets.QVBoxLayout(self)
        layout.addLayout(top)
        layout.addWidget(self.figure)
        layout.addLayout(buttons)
        layout.addLayout(tables, 1)
        layout.addWidget(self.message)
        self._timer = QtCore.QTimer(self)
        self._timer.timeout.connect(self._tick)
        self._timer.start(int(1000.0 / procedure.TARGET_RATE_HZ))
        QtWidgets.QApplication.instance().aboutToQuit.connect(self._motor_step.on_quit)
        self.enable()

    @property
    def motors(self):
        """The latest motor_check.MotorCheck, or None (none yet, or flipped)."""
        return self._motor_step.check

    # Steps ----------------------------------------------------------------------------------
    def start(self):
        """Begin a new run: forget the captures; the encoders step comes first."""
        if self.step == 'motors':
            return
        self.session, self.changes, self.check = procedure.Session(), None, None
        self.step = 'encoders'
        self.say('')
        self._advance()

    def capture(self):
        """Capture the pose shown from the latest readings and the stored settings."""
        if self.step != 'pose':
            return
        try:
            self.session.capture(self._readings, self.client.stored_settings())
        except procedure.CaptureError as error:
            self.say(str(error), error=True)
            return
        self.say('captured %d of %d' % (len(self.session.raws), len(self.session.poses)))
        self._advance()

    def retake(self):
        """Go back one pose (after the last one too, to capture it again)."""
        if self.step in ('pose', 'review') and self.session.raws:
            self.session.retake()
            self.changes, self.step = None, 'pose'
            self._advance()

    def apply(self):
        """Store the new values, all joints in one request, off the GUI thread."""
        calibration_store.apply(self)

    def undo(self):
        """Store the old values of the joints the last Apply wrote, in one step."""
        calibration_store.undo(self)

    def start_check(self):
        """Ask for each joint in turn to be moved in Baxter's positive direction."""
        if self.step == 'motors':
            return
        self.check, self.step = procedure.DirectionCheck(), 'check'
        self.say('')
        self._advance()

    def start_motors(self):
        """Check each joint's sign_motor in hold, limited to motor_check.SAFE_VOLTAGE_V."""
        stored = self.client.stored_settings()
        if self._task.busy() or self.step not in ('idle', 'review') or stored is None:
            return
        self.step = 'motors'
        self.say('')
        self._motor_step.start(stored)

    def stop_motors(self):
        """Stop the motor check: limp now, then restore the stored voltage limits."""
        if self.step == 'motors':
            self._motor_step.stop()

    def flip(self):
        """Store the flipped sign_motor of the joints the motor check found wrong."""
        if self.motors is None or not self.motors.wrong() or self._task.busy():
            return
        self._motor_step.flip(functools.partial(calibration_store.stored, self))
        self.enable()

    def pose_sim(self):
        """Set the simulated puppet's hand to the pose awaited (with the simulated puppet)."""
        pose = self.session.pose() if self.session and self.step == 'pose' else None
        if self.sim is None or pose is None:
            return
        angles = [float(a) for a in pose.angles_rad]
        self.hand_posed.emit(angles)
        self.sim.set_hand(angles)
        self.say('the virtual puppet moves to %s; capture once it is there' % pose.name)

    def _tick(self):
        """Publish the awaited pose as the target; run the motor check between stores."""
        if self.step == 'pose' and self.session.pose() is not None:
            self.client.publish_target(self.session.pose())
        if self.step == 'motors' and not self._task.busy():
            self._motor_step.tick()

    # Frames ---------------------------------------------------------------------------------
    def refresh(self, snap, now_s):
        """Take the latest readings; the end-piece button captures while a pose is awaited."""
        self._readings = [(j.status, j.angle_rad) for j in snap.joints]
        teleop = snap.teleop
        following = follow_lock.following(teleop.follow_left, teleop.follow_right) if (
            teleop and now_s - teleop.received_s <= follow_lock.TELEOP_STALE_S) else ''
        if following != self.following:
            self.following = following
            self.enable()
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
                self.say('joints %s move the wrong way: calibrate again' % wrong if wrong
                          else 'every joint moves the right way', error=bool(wrong))
                self.step = 'idle'
        self.enable()

    def _review(self):
        try:
            self.changes = self.session.changes(self.client.stored_settings())
        except (solver.SolveError, TypeError) as error:
            self.say('cannot solve: %s' % error, error=True)
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

    def enable(self):
        """Enable the buttons that make sense now."""
        busy = self._task.busy()
        flagged = self.changes is None or any(c.fit.problem for c in self.changes)
        self.buttons['Start'].setEnabled(not busy and self.step != 'motors')
        self.buttons['Capture'].setEnabled(self.step == 'pose')
        self.buttons['Retake'].setEnabled(self.step in ('pose', 'review') and not busy
                                          and bool(self.session and self.session.raws))
        # A new home or sign would move a following Baxter arm: config_X refuses it then too.
        meaning = any(n in settings.ANGLE_SETTINGS for v in self.undo_values.values() for n in v)
        self.buttons['Apply'].setEnabled(self.step == 'review' and not flagged and not busy
                                         and not self.following)
        self.buttons['Apply'].setToolTip(self.following)
        self.buttons['Undo'].setEnabled(bool(self.undo_values) and not busy
                                        and self.step != 'motors'
                                        and not (meaning and self.following))
        self.buttons['Undo'].setToolTip(self.following if meaning else '')
        self.buttons['Check'].setEnabled(not busy and self.step in ('idle', 'review'))
        self.buttons['Motors'].setEnabled(not busy and self.step in ('idle', 'review'))
        self.buttons['Stop'].setEnabled(self.step == 'motors')
        self.buttons['Flip'].setEnabled(not busy and self.step == 'idle' and
                                        bool(self.motors and self.motors.wrong()))
        self.pose_button.setEnabled(self.step == 'pose')

    def say(self, text, error=False):
        """Show a line under the table, red when error."""
        self.message.setText(text)
        paint(self.message, RED if error else GREEN)
