"""demonstrate: record scripted demonstrations of an assist task on the simulated system.

`rosrun robopuppet demonstrate --task carry_tray --episodes 6 [--seed 1]`, with main_sim
running both puppets (run_side_L:=true). Brings both Baxter arms to the task's start through
their puppets (puppet L's button 2 for the left arm, R's 3 for the right), then per episode
records one scripted execution (demonstration.demonstrate, seeds seed, seed + 1, ...) through
the recorder's service, with the task's text, and moves slowly to the next start.
"""
import argparse
import sys
import threading
import time

import numpy as np
import rosgraph
import rospy
from sensor_msgs.msg import JointState

from robopuppet import baxter_description as bd, interface
from robopuppet.assist import demonstration, tasks
from robopuppet.assist.sim_hands import FOLLOW_BUTTON, PUPPET_SIDE, SimHands, SimHandsError
from robopuppet_msgs.srv import Record

EXIT_NO_SYSTEM, EXIT_NO_PUPPET, EXIT_REFUSED, EXIT_INTERRUPTED = 1, 3, 4, 130
SIDES = ('left', 'right')
NEAR_RAD = 0.05           # Baxter counts as at a pose this near, every joint
TRANSFER_RAD_S = 0.3      # the hands move between episodes at most this fast, per joint
WAIT_S = 10.0


class Failure(Exception):
    """The command cannot go on: the message, and the exit code."""


class BaxterArms:
    """Baxter's measured arm angles from /robot/joint_states."""

    def __init__(self):
        self._lock, self._angles = threading.Lock(), {}
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on_states, queue_size=5)

    def _on_states(self, msg):
        with self._lock:
            self._angles.update(zip(msg.name, msg.position))

    def near(self, side, pose):
        with self._lock:
            angles = [self._angles.get(name) for name in bd.arm_joint_names(side)]
        return None not in angles and np.abs(np.subtract(angles, pose)).max() <= NEAR_RAD


def engage(hands, baxter, start):
    """Bring both arms to following, at start's first pose."""
    for side in SIDES:
        hands.wait(lambda: hands.teleop(side) is not None, WAIT_S,
                   'teleop_state of puppet %s' % PUPPET_SIDE[side])
        hands.grip(side, False)
        if hands.teleop(side).state == interface.CALIBRATING:
            print('calibrating puppet %s (turning its joints through their index marks)'
                  % PUPPET_SIDE[side])
            hands.calibrate(side, getattr(start, side)[0])
        hands.pose(side, getattr(start, side)[0])
        if not getattr(hands.teleop(side), 'follow_' + side):
            hands.wait(lambda: hands.teleop(side).state in (interface.READY,
                                                             interface.FOLLOWING), WAIT_S,
                       'puppet %s ready to follow' % PUPPET_SIDE[side])
            hands.press(side, FOLLOW_BUTTON[side])
        hands.wait(lambda: getattr(hands.teleop(side), 'follow_' + side), WAIT_S,
                   'Baxter %s following puppet %s' % (side, PUPPET_SIDE[side]))
    for side in SIDES:
        hands.wait(lambda: baxter.near(side, getattr(start, side)[0]), 60.0,
                   'Baxter %s arm at the start pose' % side)


def record(service, start, task_text, notes=''):
    """Start or stop an episode; return its bag file. Raises Failure when refused."""
    try:
        answer = service(start=start, notes=notes, task=task_text if start else '')
    except rospy.ServiceException as error:
        raise Failure('recording failed: %s' % error, EXIT_REFUSED) from error
    if not answer.ok:
        raise Failure('recording refused: %s' % answer.error, EXIT_REFUSED)
    return answer.episode


def run(args, hands, baxter, service):
    """Record the episodes; return the number recorded."""
    task, recording = tasks.TASKS[args.task], False
    demo = demonstration.demonstrate(args.task, args.seed)
    engage(hands, baxter, demo)
    try:
        for index in range(args.episodes):
            seed, began = args.seed + index, time.monotonic()
            if index:
                following = demonstration.demonstrate(args.task, seed)
                hands.play(demonstration.transfer(demo, following, TRANSFER_RAD_S))
                demo = following
                engage(hands, baxter, demo)   # again, should a silent puppet have stopped it
            recording = bool(record(service, True, task.text, 'scripted, seed %d' % seed))
            hands.play(demo)
            episode = record(service, False, task.text)
            recording = False
            lost = [s for s in SIDES if not getattr(hands.teleop(s), 'follow_' + s)]
            print('episode %d/%d: seed %d, %.1f s demonstrated, %.1f s in all: %s%s' % (
                index + 1, args.episodes, seed, demo.t[-1], time.monotonic() - began, episode,
                '; WARNING: Baxter %s stopped following' % ' and '.join(lost) if lost else ''),
                flush=True)
    finally:
        if recording:
            record(service, False, task.text)
            print('recording stopped', flush=True)
    return args.episodes


def main(argv=None):
    """Parse the command line, check the running system, record the episodes."""
    parser = argparse.ArgumentParser(
        description='Record scripted demonstrations of an assist task with both simulated '
                    'puppets (main_sim with run_side_L:=true).',
        epilog='Exit status: 0 done, 1 no running system (ROS master, recorder), 3 a simulated '
               'puppet missing or not following, 4 recording refused, 130 interrupted.')
    parser.add_argument('--task', required=True, choices=list(tasks.TASKS))
    parser.add_argument('--episodes', type=int, default=6)
    parser.add_argument('--seed', type=int, default=1, help='the first episode\'s seed')
    args = parser.parse_args(rospy.myargv(sys.argv if argv is None else argv)[1:])
    try:
        if not rosgraph.is_master_online():
            raise Failure('no ROS master at %s: start ./run.sh run_side_L:=true first'
                          % rosgraph.get_master_uri(), EXIT_NO_SYSTEM)
        rospy.init_node('demonstrate', anonymous=True, disable_signals=True)
        hands, baxter = SimHands(SIDES), BaxterArms()
        for side in SIDES:
            hands.wait(lambda: hands.connected(side), 5.0, 'simulated puppet %s (main_sim '
                       'run_side_%s:=true)' % (PUPPET_SIDE[side], PUPPET_SIDE[side]))
        try:
            rospy.wait_for_service(interface.RECORD_SERVICE, 5.0)
        except rospy.ROSException as error:
            raise Failure('no recorder: %s' % error, EXIT_NO_SYSTEM) from error
        run(args, hands, baxter, rospy.ServiceProxy(interface.RECORD_SERVICE, Record))
    except SimHandsError as error:
        print('demonstrate: %s' % error, file=sys.stderr)
        sys.exit(EXIT_NO_PUPPET)
    except Failure as failure:
        print('demonstrate: %s' % failure.args[0], file=sys.stderr)
        sys.exit(failure.args[1])
    except KeyboardInterrupt:
        print('demonstrate: interrupted', file=sys.stderr)
        sys.exit(EXIT_INTERRUPTED)
    finally:
        rospy.signal_shutdown('demonstrate done')
