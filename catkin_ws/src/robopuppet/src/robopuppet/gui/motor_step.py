"""The calibration tab's motor check: run a motor_check.MotorCheck, say what to do, show results.

The tab's Motors button starts it, its 10 Hz timer runs it (tick), Stop cancels it and Flip
stores the flipped sign_motor of the joints found wrong. Before and while a joint is checked
the tab says what the operator must do: with the simulated puppet, press "let go of the puppet"
on the Virtual puppet panel (its hand holds every joint, and the safe voltage cannot move a held
joint); with a real puppet, let the arm hang down and let go of the joint named. The results are
a table (joint, result), failures in red; at the end the tab says how to go on.
"""
import sys

from PyQt5 import QtGui, QtWidgets

from robopuppet import interface, settings
from robopuppet.calibration import motor_check, procedure
from robopuppet.gui.look import GREEN, RED

RESULT_TEXT = {
    motor_check.RIGHT: ('right', 'the motor pushes toward the setpoint'),
    motor_check.WRONG: ('WRONG way (Flip)', 'the motor pushes away from the setpoint: Flip '
                        'stores the flipped sign_motor'),
    motor_check.UNKNOWN: ('did not move', 'held, or too heavy for the safe voltage: let go of '
                          'it, let the arm hang down'),
}
LET_GO_SIM = ('first press "let go of the puppet" on the Virtual puppet panel: the simulated '
              'hand holds every joint, and the safe voltage cannot move a held joint.')


def joint_list(joints):
    """Return 'joint 5' or 'joints 0, 2 and 4'."""
    names = [str(j) for j in joints]
    if len(names) == 1:
        return 'joint ' + names[0]
    return 'joints %s and %s' % (', '.join(names[:-1]), names[-1])


def before_text(joint, sim_puppet):
    """Return what the operator must do while `joint` is checked."""
    how = 'in hold at %.1f V at most its setpoint moves by %.1f rad; the table fills in.' % (
        motor_check.SAFE_VOLTAGE_V, motor_check.STEP_RAD)
    if sim_puppet:
        return 'Motors, joint %d: %s Then %s' % (joint, LET_GO_SIM, how)
    return ('Motors, joint %d: let go of the puppet arm: let it hang down, hands off joint %d '
            'and everything beyond it (you may steady the links before it). Then %s'
            % (joint, joint, how))


def done_text(check, sim_puppet):
    """Return (instruction, message, failed) once the check has ended."""
    by_result = {r: [j for j, got in sorted(check.results.items()) if got == r]
                 for r in RESULT_TEXT}
    wrong, still = by_result[motor_check.WRONG], by_result[motor_check.UNKNOWN]
    parts = ['Motor check %s.' % ('stopped' if check.error else 'done')]
    if wrong:
        parts.append('Flip stores the flipped sign_motor of %s.' % joint_list(wrong))
    if still:
        parts.append('%s did not move: %s' % (joint_list(still).capitalize(), (
            'was the simulated hand still holding the puppet? Press "let go of the puppet", '
            'then Motors again.' if sim_puppet else 'was the arm held there, or the joint '
            'loaded? Let the arm hang down, let go of it, then Motors again.')))
    parts.append('Move a slider of the Virtual puppet panel to take the puppet again.'
                 if sim_puppet else 'The puppet is limp: take hold of the puppet arm again.')
    summary = '; '.join('%s: %s' % (r if r != motor_check.WRONG else 'WRONG', joint_list(js))
                        for r, js in by_result.items() if js)
    message = ('STOPPED: %s. ' % check.error if check.error else '') + (
        summary or 'no joint checked')
    return ' '.join(parts), message, bool(check.error or wrong or still)


class MotorResults(QtWidgets.QTableWidget):
    """The results table: one row per joint, its result (failures red, right green)."""

    def __init__(self, parent=None):
        super().__init__(settings.NUM_JOINTS, 2, parent)
        self.setHorizontalHeaderLabels(('joint', 'motor check'))
        self.verticalHeader().hide()
        self.horizontalHeader().setStretchLastSection(True)
        for joint in settings.JOINTS:
            self.setItem(joint, 0, QtWidgets.QTableWidgetItem('joint %d' % joint))
            self.setItem(joint, 1, QtWidgets.QTableWidgetItem(''))
        self.resizeColumnToContents(0)

    def show_check(self, check):
        """Show each joint's result, 'checking…' on the joint being checked."""
        joint = check.joint()
        for row in settings.JOINTS:
            result = check.results.get(row)
            item = self.item(row, 1)
            text, why = RESULT_TEXT[result] if result else (
                'checking…' if row == joint else '', '')
            item.setText(text)
            item.setToolTip(why)
            colour = GREEN if result == motor_check.RIGHT else RED if result else None
            item.setBackground(QtGui.QColor(colour) if colour else QtGui.QBrush())


class MotorStep:
    """Run the motor check for a CalibrationTab `tab` (its client, task, labels and buttons)."""

    def __init__(self, tab, sim_puppet):
        self.tab, self.sim_puppet = tab, sim_puppet
        self.check = None  # the latest motor_check.MotorCheck
        self.table = MotorResults()
        self.table.hide()

    def start(self, stored):
        """Check each joint's sign_motor in hold, limited to motor_check.SAFE_VOLTAGE_V."""
        self.check = motor_check.MotorCheck(stored)
        self.table.show()
        self.tab.client.set_opmode(interface.LIMP)
        self.do(self.check.start())

    def stop(self):
        """Stop: limp now, then restore the stored voltage limits."""
        if self.check.phase not in ('restore', 'done'):
            self.do(self.check.cancel())

    def flip(self, applied):
        """Store the flipped sign_motor of the wrong joints; applied(applied, error, old)."""
        wrong = self.check.wrong()
        old = {j: {'sign_motor': self.check.signs[j]} for j in wrong}
        flips = self.check.flips(wrong)
        self.tab.say('flipping sign_motor of %s…' % joint_list(wrong))
        self.tab.task.start(
            lambda: procedure.apply_changes(self.tab.client.set_arm_config, flips),
            lambda done, error: applied(done, error, 'flipped', old), self.tab.APPLY_TIMEOUT_S)
        self.check = None

    def tick(self):
        """Take the latest readings (10 Hz, not while a store runs)."""
        joints = self.tab.client.state.snapshot().joints
        self.do(self.check.update(self.tab.client.now(), [j.angle_rad for j in joints],
                                  [j.voltage_v for j in joints]))

    def do(self, command):
        """Do a motor_check.Command, then show where the check is."""
        client = self.tab.client
        if command.kind in ('limp', 'hold'):
            client.set_opmode(command.kind)
        elif command.kind == 'setpoint':
            client.set_setpoint(command.joint, command.values)
        elif command.kind == 'store':
            self.tab.task.start(
                lambda: procedure.apply_changes(client.set_arm_config, command.values),
                self._stored, self.tab.APPLY_TIMEOUT_S)
        self.show()

    def _stored(self, applied, error):
        problem = error or (applied.error if applied else '')
        self.do(self.check.stored(self.tab.client.now(), problem))

    def show(self):
        """Say what to do now and show the results."""
        check, tab, joint = self.check, self.tab, self.check.joint()
        self.table.show_check(check)
        if joint is not None:
            tab.instruction.setText(before_text(joint, self.sim_puppet))
        elif check.phase == 'restore':
            tab.instruction.setText('Motors: restoring the stored voltage limits…')
        elif check.phase == 'done':
            tab.step = 'idle'
            if 'restoring' in check.error:  # Undo tries again
                tab.undo_values = {j: dict(tab.undo_values.get(j, {}), **v)
                                   for j, v in check.restore_values().items()}
            instruction, message, failed = done_text(check, self.sim_puppet)
            tab.instruction.setText(instruction)
            tab.say(message, error=failed)
        tab.enable()

    def on_quit(self):
        """The application ends: never leave the puppet in hold at the check's limits."""
        if self.check is None or self.check.phase == 'done':
            return
        self.tab.client.set_opmode(interface.LIMP)
        restore = self.check.restore_values()
        applied = procedure.apply_changes(self.tab.client.set_arm_config, restore)
        if applied.error:
            sys.stderr.write('calibration: restoring the voltage limits failed (%s); set them '
                             'again: %s\n' % (applied.error, restore))
