"""calibrate: the calibration procedure in a terminal, `rosrun robopuppet calibrate --side R`.

Prompts for each pose of procedure.POSES (capture on Enter, 'r' takes the previous pose again,
'q' quits), solves, shows old and new values with each joint's residual, and stores them with
set_config after a 'y' (or at once with --yes; with --dry-run never). Lines may come from a
pipe, for scripts: `printf '\n\n\n\n' | rosrun robopuppet calibrate --side R --yes`.
Exit status: 0 stored (or dry run), 1 quit or no puppet, 2 a joint flagged, 3 a store failed.
"""
import argparse
import sys
import threading

import rospy
from std_msgs.msg import Float32, String

from robopuppet import interface, settings
from robopuppet.calibration import procedure
from robopuppet_msgs.msg import ArmSettings
from robopuppet_msgs.srv import SetConfig

WAIT_S = 10.0


class ArmReader:
    """Keep the latest encoder statuses, angles and stored settings of one puppet arm.

    Subscribes (under /puppet/arm_<side>): joint_J/enc_stat, joint_J/angle, stored_settings.
    Calls: set_config (robopuppet_msgs/SetConfig).
    """

    def __init__(self, side):
        self._lock = threading.Lock()
        self._readings = [(None, float('nan'))] * settings.NUM_JOINTS
        self._stored = None
        ns = interface.puppet_ns(side)
        self._subs = [rospy.Subscriber('%s/%s' % (ns, interface.STORED_SETTINGS), ArmSettings,
                                       self._on_stored, queue_size=1)]
        for joint in settings.JOINTS:
            self._subs += [
                rospy.Subscriber(interface.joint_topic(side, joint, 'enc_stat'), String,
                                 self._on_reading, callback_args=(joint, 0), queue_size=10),
                rospy.Subscriber(interface.joint_topic(side, joint, 'angle'), Float32,
                                 self._on_reading, callback_args=(joint, 1), queue_size=10)]
        self._set = rospy.ServiceProxy('%s/%s' % (ns, interface.SET_CONFIG), SetConfig)

    def _on_stored(self, msg):
        stored = {j.joint: {n: getattr(j, n) for n in settings.NAMES} for j in msg.joints}
        with self._lock:
            self._stored = stored

    def _on_reading(self, msg, where):
        joint, field = where
        with self._lock:
            reading = list(self._readings[joint])
            reading[field] = msg.data
            self._readings[joint] = tuple(reading)

    def readings(self):
        """Return (status, angle rad) per joint and the stored settings (None before any)."""
        with self._lock:
            return list(self._readings), self._stored

    def set_config(self, joint, values):
        """Store {name: value} of a joint, all or none; RuntimeError when the call fails."""
        try:
            self._set.wait_for_service(WAIT_S)
            return self._set(joint, list(values), list(values.values()))
        except (rospy.ROSException, rospy.ServiceException) as error:
            raise RuntimeError(str(error)) from None


def ask(prompt):
    """Return a line typed by the operator (stripped), or 'q' at the end of the input."""
    try:
        return input(prompt).strip().lower()
    except EOFError:
        return 'q'


def table(changes):
    """Return the old and new values of each joint, its residual and any problem, as text."""
    lines = ['joint  home_angle old -> new (rad)  sign_angle old -> new  residual (rad)']
    for c in changes:
        lines.append('%5d  %8.4f -> %8.4f  %+4.0f -> %+4.0f  %8.4f  %s' % (
            c.joint, c.old['home_angle'], c.new['home_angle'], c.old['sign_angle'],
            c.new['sign_angle'], c.fit.residual_rad, c.fit.problem))
    return '\n'.join(lines)


def run(reader, assume_yes, dry_run):
    """Run the procedure against an ArmReader; return the exit status."""
    deadline = rospy.get_time() + WAIT_S
    while reader.readings()[1] is None or None in [r[0] for r in reader.readings()[0]]:
        if rospy.is_shutdown() or rospy.get_time() > deadline:
            print('no stored settings or joint statuses within %g s: are config_X and '
                  'serial_X running?' % WAIT_S)
            return 1
        rospy.sleep(0.1)
    while procedure.joints_to_turn(reader.readings()[0]):
        turn = procedure.joints_to_turn(reader.readings()[0])
        if ask('Turn joints %s through their index mark (0 rad), then press Enter: '
               % turn) == 'q':
            return 1
    session = procedure.Session()
    while session.pose() is not None:
        pose = session.pose()
        print('Pose %d of %d, %s (rad): %s' % (len(session.raws) + 1, len(session.poses),
                                              pose.name, ' '.join('%+.2f' % a
                                                                  for a in pose.angles_rad)))
        answer = ask('Pose the puppet so, then press Enter to capture (r: previous pose again, '
                     'q: quit): ')
        if answer == 'q':
            return 1
        if answer == 'r':
            session.retake()
            continue
        try:
            session.capture(*reader.readings())
        except procedure.CaptureError as error:
            print(error)
    changes = session.changes(reader.readings()[1])
    print(table(changes))
    if any(c.fit.problem for c in changes):
        print('Nothing stored: capture the flagged poses again.')
        return 2
    if dry_run or not (assume_yes or ask('Store the new values? [y/N] ') == 'y'):
        print('Nothing stored.')
        return 0 if dry_run else 1
    applied = procedure.apply_changes(reader.set_config, {c.joint: c.new for c in changes})
    print('stored joints %s' % applied.written)
    if applied.error:
        print('STORE FAILED: %s. The joints above keep their new values; the old ones are in '
              'the table.' % applied.error)
        return 3
    return 0


def main(argv=None):
    """Parse the command line, start the node and run the procedure."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--side', required=True, choices=interface.PUPPET_SIDES)
    parser.add_argument('--yes', action='store_true', help='store without asking')
    parser.add_argument('--dry-run', action='store_true', help='solve and show, store nothing')
    args = parser.parse_args(rospy.myargv(sys.argv if argv is None else argv)[1:])
    rospy.init_node('calibrate_%s' % args.side, anonymous=True, disable_signals=True)
    sys.exit(run(ArmReader(args.side), args.yes, args.dry_run))
