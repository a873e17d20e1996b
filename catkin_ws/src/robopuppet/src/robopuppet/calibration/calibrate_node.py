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
import threading
import time

import rosgraph
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32, String

from robopuppet import interface, settings
from robopuppet.calibration import procedure, prompt
from robopuppet_msgs.msg import ArmSettings, JointChange
from robopuppet_msgs.srv import SetArmConfig

WAIT_S = 10.0
MASTER_TIMEOUT_S = 3.0  # no answer from ROS_MASTER_URI within this: say so and exit 1
SIM_DELIVERY_S = 5.0  # sim_pose waits this long for the simulated puppet to take the pose


class ArmReader:
    """Keep the latest encoder statuses, angles and stored settings of one puppet arm.

    Subscribes (under /puppet/arm_<side>): joint_J/enc_stat, joint_J/angle, stored_settings.
    Calls: set_arm_config (robopuppet_msgs/SetArmConfig).
    Publishes: calibration_target (sensor_msgs/JointState, procedure.TARGET_TOPIC) at
        procedure.TARGET_RATE_HZ while show_target has a pose, nothing otherwise;
        /puppet_sim/arm_<side>/hand (sensor_msgs/JointState, latched) on pose_sim only.
    """

    def __init__(self, side):
        self._lock = threading.Lock()
        self._readings = [(None, float('nan'))] * settings.NUM_JOINTS
        self._stored = None
        self.side, self._target = side, None
        ns = interface.puppet_ns(side)
        self._target_pub = rospy.Publisher('%s/%s' % (ns, procedure.TARGET_TOPIC), JointState,
                                           queue_size=1)
        self._timer = rospy.Timer(rospy.Duration(1.0 / procedure.TARGET_RATE_HZ),
                                  self._publish_target)
        self._subs = [rospy.Subscriber('%s/%s' % (ns, interface.STORED_SETTINGS), ArmSettings,
                                       self._on_stored, queue_size=1)]
        for joint in settings.JOINTS:
            self._subs += [
                rospy.Subscriber(interface.joint_topic(side, joint, 'enc_stat'), String,
                                 self._on_reading, callback_args=(joint, 0), queue_size=10),
                rospy.Subscriber(interface.joint_topic(side, joint, 'angle'), Float32,
                                 self._on_reading, callback_args=(joint, 1), queue_size=10)]
        self._set = rospy.ServiceProxy('%s/%s' % (ns, interface.SET_ARM_CONFIG), SetArmConfig)
        self._hand_pub = hand_publisher(side)

    def sim_running(self):
        """Return True when a simulated puppet listens to its hand topic."""
        return self._hand_pub.get_num_connections() > 0

    def pose_sim(self, angles_rad):
        """Move the simulated puppet's hand to seven angles (rad)."""
        publish_hand(self._hand_pub, angles_rad)

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

    def show_target(self, pose):
        """Publish a procedure.Pose as the calibration target from now on (None: stop)."""
        with self._lock:
            self._target = pose

    def _publish_target(self, _event):
        with self._lock:
            pose = self._target
        if pose is not None:
            names, positions = procedure.target_state(self.side, pose)
            self._target_pub.publish(JointState(name=names, position=positions,
                                                header=rospy.Header(stamp=rospy.Time.now())))

    def readings(self):
        """Return (status, angle rad) per joint and the stored settings (None before any)."""
        with self._lock:
            return list(self._readings), self._stored

    def set_arm_config(self, values):
        """Store {joint: {name: value}} in one request, all or none; RuntimeError when the call
        fails."""
        try:
            self._set.wait_for_service(WAIT_S)
            return self._set([JointChange(joint, list(v), list(v.values()))
                              for joint, v in values.items()])
        except (rospy.ROSException, rospy.ServiceException) as error:
            raise RuntimeError(str(error)) from None


def hand_publisher(side):
    """Return a latched publisher of the simulated puppet's hand (interface.SIM_HAND)."""
    return rospy.Publisher('%s/%s' % (interface.sim_ns(side), interface.SIM_HAND), JointState,
                           queue_size=1, latch=True)


def publish_hand(publisher, angles_rad):
    """Publish seven hand angles (rad) as the GUI's virtual puppet panel does."""
    msg = JointState(name=list(settings.JOINT_NAMES), position=[float(a) for a in angles_rad])
    msg.header.stamp = rospy.Time.now()
    publisher.publish(msg)


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


def ask(text):
    """Return a line typed by the operator (prompt.ask)."""
    return prompt.ask(text)


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
        reader.show_target(pose)
        print('Pose %d of %d, %s' % (len(session.raws) + 1, len(session.poses), pose.name))
        print('  target (rad): %s' % procedure.readout([(None, a) for a in pose.angles_rad]))
        sim = reader.sim_running()
        answer = prompt.ask_live(
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
                print('the virtual puppet moves to %s: press Enter once it is there' % pose.name)
            else:
                print('no simulated puppet listens on %s/%s' % (interface.sim_ns(reader.side),
                                                                 interface.SIM_HAND))
            continue
        try:
            session.capture(*reader.readings())
        except procedure.CaptureError as error:
            print(error)
    reader.show_target(None)
    changes = session.changes(reader.readings()[1])
    print(procedure.changes_table(changes))
    if any(c.fit.problem for c in changes):
        print('Nothing stored: capture the flagged poses again.')
        return 2
    if dry_run or not (assume_yes or ask('Store the new values? [y/N] ') == 'y'):
        print('Nothing stored.')
        return 0 if dry_run else 1
    applied = procedure.apply_changes(reader.set_arm_config, {c.joint: c.new for c in changes})
    if applied.error:
        print('STORE FAILED: %s. Nothing stored: every joint keeps its old values (in the '
              'table).' % applied.error)
        return 3
    print('stored joints %s' % applied.written)
    return 0


def main(argv=None):
    """Parse the command line, start the node and run the procedure."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0],
                                     epilog=prompt.KEYS_AND_EXIT_CODES,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--side', required=True, choices=interface.PUPPET_SIDES)
    parser.add_argument('--yes', action='store_true', help='store without asking')
    parser.add_argument('--dry-run', action='store_true', help='solve and show, store nothing')
    args = parser.parse_args(rospy.myargv(sys.argv if argv is None else argv)[1:])
    problem = master_problem()
    if problem:
        print('calibrate: %s' % problem, file=sys.stderr)
        sys.exit(1)
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
    problem = master_problem()
    if problem:
        print('sim_pose: %s' % problem, file=sys.stderr)
        sys.exit(1)
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
