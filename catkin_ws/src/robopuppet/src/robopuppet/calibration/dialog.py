"""The calibrate command's dialog: turn the quadrature joints, capture each pose, solve, store.

Pure: the arm is an object with readings(), show_target(pose), sim_running(), pose_sim(angles),
side and set_arm_config(values) (calibrate_node's ArmReader, or a test's fake); the operator's
answers come from prompt (or the ask and ask_live given), what is shown goes to say.
"""
from robopuppet import interface
from robopuppet.calibration import procedure, prompt


def converse(reader, assume_yes, dry_run, ask=prompt.ask, ask_live=prompt.ask_live, say=print):
    """Run the procedure once the arm reports; return the exit status (prompt's exit codes)."""
    while procedure.joints_to_turn(reader.readings()[0]):
        turn = procedure.joints_to_turn(reader.readings()[0])
        if ask('Turn joints %s through their index mark (0 rad), then press Enter: '
               % turn) == 'q':
            return 1
    session = procedure.Session()
    while session.pose() is not None:
        pose = session.pose()
        reader.show_target(pose)
        say('Pose %d of %d, %s' % (len(session.raws) + 1, len(session.poses), pose.name))
        say('  target (rad): %s' % procedure.readout([(None, a) for a in pose.angles_rad]))
        sim = reader.sim_running()
        answer = ask_live(
            'Pose the puppet so, then press Enter to capture (r: previous pose again, %sq: quit): '
            % ('p: pose the virtual puppet, ' if sim else ''),
            lambda: '  now    (rad): %s' % procedure.readout(reader.readings()[0]))
        if answer == 'q':
            return 1
        if answer == 'r':
            session.retake()
            continue
        if answer == 'p':
            if sim:
                reader.pose_sim(pose.angles_rad)
                say('the virtual puppet moves to %s: press Enter once it is there' % pose.name)
            else:
                say('no simulated puppet listens on %s/%s' % (interface.sim_ns(reader.side),
                                                               interface.SIM_HAND))
            continue
        try:
            session.capture(*reader.readings())
        except procedure.CaptureError as error:
            say(error)
    reader.show_target(None)
    changes = session.changes(reader.readings()[1])
    say(procedure.changes_table(changes))
    if any(c.fit.problem for c in changes):
        say('Nothing stored: capture the flagged poses again.')
        return 2
    if dry_run or not (assume_yes or ask('Store the new values? [y/N] ') == 'y'):
        say('Nothing stored.')
        return 0 if dry_run else 1
    applied = procedure.apply_changes(reader.set_arm_config, {c.joint: c.new for c in changes})
    if applied.error:
        say('STORE FAILED: %s. Nothing stored: every joint keeps its old values (in the '
            'table).' % applied.error)
        return 3
    say('stored joints %s' % applied.written)
    return 0
