"""The terminal command move_arms: bring Baxter's arms slowly to a pose, clear of the zones.

    rosrun robopuppet move_arms [--arms left,right] [--angles A,A,A,A,A,A,A] [--side L|R|LR]
                                [--zones FILE]

The pose is Baxter's neutral pose (baxter_description.NEUTRAL_POSE: where the stand-in starts
and Rethink's SDK's move_to_neutral goes) unless --angles gives seven joint angles (rad,
s0 s1 e0 e1 w0 w1 w2), the same for each arm named. The way keeps clear of what lies below the
arms (the patient): the shoulder (s1) rises LIFT_RAD above the higher of the two poses first,
then the other joints turn to the pose's, then the shoulder comes down to it. It is a replay
(robopuppet.episodes.replay) of that path, timed at replay.APPROACH_SPEED_RAD_S on the joint
that moves most, so every rule of the replay holds: joint limits, the velocity limits, no
jump, the keep-out zones (--zones as for replay: by default the running arm controllers';
held at one for replay.ZONE_WAIT_S: stopped), and its stop rules: button 1 of a puppet side
of --side (default both), a puppet starting to follow (refused when one follows at the
start), Baxter disabled, /puppet/replay_stop. Unlike a replay, a puppet that moves does not
stop it: a study device that shows Baxter's pose moves with the arm. The grippers are left as
they are. Exit code 0: the arms are there; 1: stopped by a stop rule (a message says which);
2: refused.

The study runner (robopuppet.study.study_node) brings the arms to their start with it before
every trial.
"""
import argparse
import math
import sys

import numpy as np
import rospy
from sensor_msgs.msg import JointState

from robopuppet import baxter_description
from robopuppet import interface as ifc
from robopuppet.arm.readings import arm_poses
from robopuppet.episodes import export, replay, robot_player
from robopuppet.episodes.recording import parse_sides

NEUTRAL = tuple(baxter_description.NEUTRAL_POSE[s] for s in baxter_description.ARM_JOINT_SUFFIXES)
LIFT_RAD = 0.4       # the shoulder (s1, negative is up) this much above both poses on the way
SHOULDER = 1         # s1's index
MIN_LEG_S = 0.1


def parse_angles(text):
    """Return seven finite angles (rad) from 'a,a,a,a,a,a,a' (commas or spaces).

    Raises:
        ValueError: not seven numbers, or one not finite.
    """
    try:
        angles = [float(a) for a in text.replace(',', ' ').split()]
    except ValueError:
        raise ValueError('--angles takes seven numbers (rad), got %r' % (text,)) from None
    if len(angles) != 7 or not all(math.isfinite(a) for a in angles):
        raise ValueError('--angles takes seven finite angles (rad, s0 s1 e0 e1 w0 w1 w2), '
                         'got %r' % (text,))
    return tuple(angles)


def parse_arms(text):
    """Return the Baxter arms named in 'left,right' (commas or spaces), in interface order.

    Raises:
        ValueError: none named, or a name that is not an arm.
    """
    names = set(text.replace(',', ' ').split())
    if not names or not names <= set(ifc.BAXTER_SIDES):
        raise ValueError('--arms names Baxter arms (left, right), got %r' % (text,))
    return tuple(s for s in ifc.BAXTER_SIDES if s in names)


def lifted_script(here, angles, limits, speed_rad_s=replay.APPROACH_SPEED_RAD_S):
    """Return (paths, grips) of replay.Replay bringing each arm of here ({arm: 7 angles, where
    it is}) to `angles` the lifted way (module docstring), each leg timed at speed_rad_s on the
    joint that moves most; no gripper command. The first sample (only the shoulder raised) is
    where the replay's approach goes."""
    paths, goal = {}, np.asarray(angles, float)
    for arm, start in here.items():
        start = np.asarray(start, float)
        shoulder = max(min(start[SHOULDER], goal[SHOULDER]) - LIFT_RAD, limits[arm][SHOULDER].lower)
        points = [start.copy(), goal.copy(), goal]
        points[0][SHOULDER] = points[1][SHOULDER] = shoulder
        times = np.cumsum([0.0] + [max(np.abs(b - a).max() / speed_rad_s, MIN_LEG_S)
                                   for a, b in zip(points, points[1:])])
        paths[arm] = export.Samples(times, np.array(points))
    return paths, {arm: [] for arm in here}


def measured(arms, timeout_s=robot_player.WAIT_S):
    """Return {arm: 7 angles} of Baxter's arms from one /robot/joint_states (ROSException: none
    came within timeout_s)."""
    msg = rospy.wait_for_message(ifc.ROBOT_JOINT_STATES, JointState, timeout_s)
    names = {arm: baxter_description.arm_joint_names(arm) for arm in arms}
    poses, _ = arm_poses(msg.name, msg.position, msg.velocity, names)
    if set(poses) != set(arms):
        raise rospy.ROSException('/robot/joint_states lacks the %s arm' % ' and '.join(
            sorted(set(arms) - set(poses))))
    return poses


def main(argv=None):
    """Parse the arguments, move the arms, exit with the exit code."""
    parser = argparse.ArgumentParser(prog='move_arms', description=__doc__.split('\n')[0])
    parser.add_argument('--arms', default='left,right',
                        help='Baxter arms to move (default: left,right)')
    parser.add_argument('--angles', help="seven joint angles (rad, s0 s1 e0 e1 w0 w1 w2) for "
                                         "each arm (default: Baxter's neutral pose)")
    parser.add_argument('--side', default=''.join(ifc.PUPPET_SIDES),
                        help='puppet sides whose button 1 or follow stops the motion '
                             '(default: LR)')
    parser.add_argument('--zones', metavar='FILE',
                        help="keep-out zone file (/dev/null: none; default as for replay: "
                             "the running arm controllers' zones_file)")
    args = parser.parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])

    def say(text):
        print('move_arms: %s' % text, file=sys.stderr, flush=True)
    try:
        arms, sides = parse_arms(args.arms), parse_sides(args.side)
        angles = NEUTRAL if args.angles is None else parse_angles(args.angles)
    except ValueError as error:
        parser.error(str(error))
    rospy.init_node('move_arms', anonymous=True)
    try:
        guards = robot_player.keepout_zones(args.zones, say)
    except ValueError as error:   # a bad zone file (ZoneFileError) or robot description
        say('refused: %s' % error)
        sys.exit(2)
    limits = {s: baxter_description.arm_limits(s) for s in ifc.BAXTER_SIDES}
    try:
        paths, grips = lifted_script(measured(arms), angles, limits)
    except rospy.ROSException as error:
        say("refused: Baxter's pose is unknown: %s" % error)
        sys.exit(2)
    core = replay.Replay(paths, grips, limits, 1.0, 1.0 / robot_player.RATE_HZ,
                         puppet_moved_rad=math.inf, guards=guards)
    sys.exit(robot_player.RobotPlayer(core, sides, say).run())
