"""The calibration tab's stores: Apply, Undo, and what every store's answer means (Flip's too).

Each store is one all-or-none set_arm_config request (procedure.apply_changes) run on the tab's
ConfigTask, off the GUI thread; `tab` is a CalibrationTab.
"""
from robopuppet.calibration import procedure

APPLY_TIMEOUT_S = 10.0  # one set_arm_config call: up to 1 s for the service, then the write


def apply(tab):
    """Store the new values, all joints in one request, off the GUI thread."""
    if tab.step != 'review' or tab.task.busy():
        return
    if tab.following:
        tab.say('not applied: %s' % tab.following, error=True)
        return
    old = {c.joint: c.old for c in tab.changes}
    new = {c.joint: c.new for c in tab.changes}
    tab.say('storing the new values…')
    tab.task.start(lambda: procedure.apply_changes(tab.client.set_arm_config, new),
                   lambda applied, error: stored(tab, applied, error, 'new', old),
                   APPLY_TIMEOUT_S)
    tab.enable()


def undo(tab):
    """Store the old values of the joints the last Apply wrote, in one step."""
    if not tab.undo_values or tab.task.busy() or tab.step == 'motors':
        return
    old = dict(tab.undo_values)
    tab.say('restoring the old values…')
    tab.task.start(lambda: procedure.apply_changes(tab.client.set_arm_config, old),
                   lambda applied, error: stored(tab, applied, error, 'old', None),
                   APPLY_TIMEOUT_S)
    tab.enable()


def stored(tab, applied, error, which, old):
    """A store ended: old is {joint: old values} after Apply, None after Undo."""
    written = applied.written if applied else []
    if old is None:  # what Undo could not restore stays to undo
        tab.undo_values = {j: v for j, v in tab.undo_values.items() if j not in written}
    elif written:  # a refused store wrote nothing: the last Apply's undo stays
        tab.undo_values = {j: old[j] for j in written}
        if tab.step == 'review':
            tab.step = 'idle'
    problem = error or (applied.error if applied else '')
    if problem:
        tab.say('FAILED: %s. The %s values were not stored: every joint keeps what it '
                'had.' % (problem, which), error=True)
    else:
        tab.instruction.setText('Stored. Check tests each joint\'s direction; Undo restores '
                                'the old values.' if tab.undo_values else 'Restored.')
        tab.say('stored the %s values of joints %s%s' % (
            which, written, '; Undo restores the old ones' if tab.undo_values else ''))
    tab.enable()
