"""calibrate: the calibration procedure in a terminal, `rosrun robopuppet calibrate --side R`.

Prompts for each pose of procedure.POSES (capture on Enter, 'r' takes the previous pose again,
'p' poses the simulated puppet so, 'q' quits; the reported angles shown live), solves, shows
old and new values with each joint's residual, and stores them all or none with one
set_arm_config request after a 'y' (or at once with --yes; with --dry-run never).
Lines may come from a pipe, for scripts (tests/integration/test_calibration_command.py), each
Enter sent once the puppet is posed. While a pose is awaited it is published for RViz's
calibration target ghost. Exit status: 0 stored (or dry run), 1 quit, Ctrl-C, no master or no
puppet, 2 a joint flagged, 3 the store failed (nothing stored). With no ROS master it says so
within MASTER_TIMEOUT_S.

`rosrun robopuppet sim_pose --side R "pose A"` (sim_pose_main) sets the simulated puppet's hand
to a pose of procedure.POSES by name, or to seven typed angles (rad).
"""
import argparse
import socket
import sys
import time

import rosgraph
import rospy

from robopuppet import interface
from robopuppet.calibration import dialog, procedure, prompt
from robopuppet.calibration.arm_reader import WAIT_S, ArmReader, hand_publisher, publish_hand

MASTER_TIMEOUT_S = 3.0  # no answer from ROS_MASTER_URI within this: say so and exit 1
SIM_DELIVERY_S = 5.0  # sim_pose waits this long for the simulated puppet to take the pose


def master_problem(timeout_s=MASTER_TIMEOUT_S):
    """Return '' when the ROS master of ROS_MASTER_URI answers within timeout_s, else why not."""
    uri = rosgraph.get_master_uri()
    old = socket.getdefaulttimeout()
    socket.setdefaulttimeout(timeout_s)
    try:
        rosgraph.Master('/calibrate').getPid()
    except (OSError, rosgraph.MasterException) as error:
        return ('no ROS master at %s (%s): start roscore or the RoboPuppet launch file, or set '
                'ROS_MASTER_URI' % (uri, error))
    finally:
        socket.setdefaulttimeout(old)
    return ''


def _exit_without_master(command):
    """Say why and exit 1 when no ROS master answers (master_problem)."""
    problem = master_problem()
    if problem:
        print('%s: %s' % (command, problem), file=sys.stderr)
        sys.exit(1)


def run(reader, assume_yes, dry_run):
    """Wait for the arm's readings, then run the dialog; return the exit status."""
    deadline = rospy.get_time() + WAIT_S
    while reader.readings()[1] is None or None in [r[0] for r in reader.readings()[0]]:
        if rospy.is_shutdown() or rospy.get_time() > deadline:
            print('no stored settings or joint statuses within %g s: are config_X and '
                  'serial_X running?' % WAIT_S)
            return 1
        rospy.sleep(0.1)
    return dialog.converse(reader, assume_yes, dry_run)


def main(argv=None):
    """Parse the command line, start the node and run the procedure."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0],
                                     epilog=prompt.KEYS_AND_EXIT_CODES,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--side', required=True, choices=interface.PUPPET_SIDES)
    parser.add_argument('--yes', action='store_true', help='store without asking')
    parser.add_argument('--dry-run', action='store_true', help='solve and show, store nothing')
    args = parser.parse_args(rospy.myargv(sys.argv if argv is None else argv)[1:])
    _exit_without_master('calibrate')
    rospy.init_node('calibrate_%s' % args.side, anonymous=True, disable_signals=True)
    try:
        status = run(ArmReader(args.side), args.yes, args.dry_run)
    except KeyboardInterrupt:
        print('\ninterrupted: nothing more stored')
        status = 1
    rospy.signal_shutdown('calibrate done')
    sys.exit(status)


def sim_pose_main(argv=None):
    """`sim_pose --side R POSE`: set the simulated puppet's hand to a named or typed pose."""
    parser = argparse.ArgumentParser(
        description='Set the simulated puppet\'s hand to a pose (the puppet moves there at up to '
                    '3 rad/s; the hand then holds it).',
        epilog='poses: %s, or seven angles in rad, e.g. 0 -0.5 0 0.5 0 0.5 0. Exit status 0 '
               'delivered, 1 no ROS master or no simulated puppet listening, 2 not a pose.'
               % ', '.join(repr(p.name) for p in procedure.POSES))
    parser.add_argument('--side', required=True, choices=interface.PUPPET_SIDES)
    parser.add_argument('pose', nargs='+', help='a pose name or seven angles (rad)')
    args = parser.parse_args(rospy.myargv(sys.argv if argv is None else argv)[1:])
    try:
        pose = procedure.pose_from_words(args.pose)
    except ValueError as error:
        parser.error(str(error))
    _exit_without_master('sim_pose')
    rospy.init_node('sim_pose_%s' % args.side, anonymous=True, disable_signals=True)
    publisher = hand_publisher(args.side)
    deadline = time.monotonic() + SIM_DELIVERY_S
    while publisher.get_num_connections() == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
    if publisher.get_num_connections() == 0:
        print('sim_pose: no simulated puppet listens on %s/%s within %g s' % (
            interface.sim_ns(args.side), interface.SIM_HAND, SIM_DELIVERY_S), file=sys.stderr)
        rospy.signal_shutdown('no simulated puppet')
        sys.exit(1)
    publish_hand(publisher, pose.angles_rad)
    time.sleep(0.5)  # a latched message goes out on the connection's own thread
    print('hand of the simulated puppet %s: %s (rad) %s' % (
        args.side, pose.name, procedure.readout([(None, a) for a in pose.angles_rad])))
    rospy.signal_shutdown('sim_pose done')
