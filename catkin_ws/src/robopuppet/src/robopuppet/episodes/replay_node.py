"""The terminal command replay: play a recorded episode back onto the robot or into the puppet.

    rosrun robopuppet replay EPISODE [--speed S] [--side L|R|LR] [--arms left,right]
                             [--zones FILE]
    rosrun robopuppet replay EPISODE --into puppet [--side L|R|LR] [--speed S]

Onto the robot (default) it drives robopuppet.episodes.replay through Baxter's own API (the
stand-in's too); into the puppet, robopuppet.episodes.puppet_playback through
robopuppet.episodes.puppet_player. Exit code 0: the episode played to its end; 1: stopped by a
stop rule; 2: refused or failed (a message says why).

Onto the robot the replay keeps Baxter's arms out of the keep-out zones (docs/zones.md): a
command that would take an arm into one stops the replay unsent (exit 1, naming zone, link and
arm). The zones: --zones FILE (/dev/null, an empty file: none); by default those of the running
arm controllers, their zones_file parameters (/arm_L/zones_file, /arm_R/zones_file, set by
arm.launch; '' for none), all of them when the two differ; with neither set, the package's
config/zones.yaml. A bad zone file refuses the replay (exit 2).
"""
import argparse
import json
import sys
import time

import rospy
from baxter_core_msgs.msg import AssemblyState, EndEffectorCommand, EndEffectorState, JointCommand
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, UInt8

from robopuppet import baxter_description
from robopuppet import interface as ifc
from robopuppet.arm import zone_topics
from robopuppet.arm.baxter_upkeep import CMD_GO
from robopuppet.arm.readings import arm_poses, joint_angles
from robopuppet.episodes import (export, export_cli, export_files, puppet_playback,
                                 puppet_player, replay)
from robopuppet.episodes.player import Player
from robopuppet.episodes.recording import parse_sides
from robopuppet_msgs.msg import TeleopState

RATE_HZ = 100.0
WAIT_S = 5.0        # for Baxter's state and pose before refusing


class ReplayNode(Player):
    """Replay one episode; run() returns the exit code.

    Subscribes: /robot/state, /robot/joint_states, Baxter's gripper states, and per watched
    puppet side user_btn, joint_states and teleop_state; interface.REPLAY_STOP (Empty).
    Publishes: /robot/limb/<side>/joint_command (POSITION_MODE, RATE_HZ) and
    /robot/end_effector/<side>_gripper/command ('go') of the replayed arms.
    Parameters (main reads them unless --zones is given): /arm_L/zones_file and
    /arm_R/zones_file, the arm controllers' ~zones_file: the keep-out zones the core keeps.
    """

    def __init__(self, core, sides, say):
        super().__init__(core, say)
        self._enabled = self._following = None
        self._gripper_id, self._sequence = {}, 0
        self._names = {s: baxter_description.arm_joint_names(s) for s in ifc.BAXTER_SIDES}
        self._arm = {s: rospy.Publisher(ifc.limb_topic(s, 'joint_command'), JointCommand,
                                        queue_size=10, tcp_nodelay=True) for s in core.paths}
        self._grip = {s: rospy.Publisher(ifc.baxter_gripper_topic(s, 'command'),
                                         EndEffectorCommand, queue_size=10) for s in core.paths}
        sub = rospy.Subscriber
        sub(ifc.ROBOT_STATE, AssemblyState, self._on_robot_state, queue_size=10)
        sub(ifc.ROBOT_JOINT_STATES, JointState, self._on_joints, queue_size=10)
        for s in core.paths:
            sub(ifc.baxter_gripper_topic(s, 'state'), EndEffectorState,
                lambda m, s=s: self._gripper_id.__setitem__(s, m.id), queue_size=1)
        for side in sides:
            ns = ifc.puppet_ns(side)
            sub(ns + '/' + ifc.USER_BUTTON, UInt8, lambda m: self._call(core.on_button, m.data))
            sub('%s/%s' % (ns, ifc.JOINT_STATES), JointState,
                lambda m, side=side: self._on_puppet(side, m), tcp_nodelay=True)
            sub(ns + '/' + ifc.TELEOP_STATE, TeleopState, self._on_teleop)
        sub(ifc.REPLAY_STOP, Empty, lambda m: self._call(core.stop, 'stop requested'))

    def _on_robot_state(self, msg):
        self._enabled = msg.enabled and not msg.stopped and not msg.error
        if self.core.phase is not None:
            self._call(self.core.on_robot_enabled, self._enabled)

    def _on_joints(self, msg):
        poses, speeds = arm_poses(msg.name, msg.position, msg.velocity, self._names)
        age_s = (rospy.Time.now() - msg.header.stamp).to_sec() if msg.header.stamp else 0.0
        self._call(self.core.on_robot_pose, poses, speeds, age_s)

    def _on_puppet(self, side, msg):
        try:
            self._call(self.core.on_puppet, side, joint_angles(msg.name, msg.position))
        except ValueError:
            pass  # not the puppet's seven joints: no reading of where it is

    def _on_teleop(self, msg):
        self._following = bool(msg.follow_left or msg.follow_right)
        if self.core.phase is not None:
            self._call(self.core.on_following, self._following)

    def _send(self, step):
        for side, angles in step.commands.items():
            self._arm[side].publish(JointCommand(mode=JointCommand.POSITION_MODE,
                                                 command=angles, names=self._names[side]))
        for grip in step.grips:
            self._sequence += 1
            self._grip[grip.side].publish(EndEffectorCommand(
                id=self._gripper_id.get(grip.side, 0), command=CMD_GO,
                args=json.dumps({'position': grip.position}), sender=rospy.get_name(),
                sequence=self._sequence))

    def run(self):
        """Check, approach, play; return the exit code (0 finished, 1 stopped, 2 refused)."""
        deadline = time.monotonic() + WAIT_S
        while not rospy.is_shutdown() and time.monotonic() < deadline and (
                self._enabled is None or any(self.core.robot.now(s, time.monotonic()) is None
                                             for s in self.core.paths)):
            time.sleep(0.05)
        time.sleep(0.2)  # latched teleop_state
        if not self._enabled:
            self._say('refused: Baxter is not enabled or not there (no /robot/state)')
            return 2
        if self._following:
            self._say('refused: the puppet is following Baxter: press its follow button to '
                      'stop following first, it would fight the replay')
            return 2
        with self._lock:
            self._send(self.core.start(time.monotonic()))
        if self.core.phase == replay.APPROACH:
            self._say('moving slowly to the start pose of %s' % ', '.join(
                sorted(self.core.paths)))
        self._play('replay', RATE_HZ, 1.0)
        if self.core.phase == replay.FINISHED:
            self._say('finished')
            return 0
        self._say('stopped: %s' % (self.core.why or 'shut down'))
        return 1


def keepout_zones(given, say):
    """Return {Baxter side: ZoneGuard} ({} when every file is '') of the zones the replay keeps
    the arms out of, and say which (module docstring: --zones FILE, else the running arm
    controllers', else the package's).

    Raises:
        ValueError: a zone file is bad (the message names it and the entry).
    """
    if given is not None:
        files, whose = [given], '--zones'
    else:
        running = zone_topics.controllers_zones_files()
        files = sorted(set(running.values())) or [zone_topics.package_zones_file()]
        whose = ("%s zones_file%s" % (" and ".join("arm_%s's" % s for s in sorted(running)),
                                      ' differ: the zones of both' if len(files) > 1 else '')
                 if running else "the package's: no arm controller's zones_file is set")
    guards, found = zone_topics.load_guards(*files)
    say('keep-out zones: %s (%d zone%s, %s)' % (' and '.join(p or "''" for p in files),
                                                 len(found), 's'[len(found) == 1:], whose))
    return guards


def main(argv=None):
    """Parse the arguments, replay the episode, exit with the exit code."""
    parser = argparse.ArgumentParser(prog='replay', description=__doc__.split('\n')[0])
    parser.add_argument('episode', help='a name in the episodes directory, or a .bag/.yaml')
    parser.add_argument('--into', choices=('robot', 'puppet'), default='robot',
                        help="robot: Baxter's recorded commands (default); puppet: the "
                             "recorded puppet angles as setpoints into the puppet in hold")
    parser.add_argument('--speed', type=float, default=1.0,
                        help='speed factor, 0 < S <= %g (default 1; the joints never exceed '
                             'their velocity limits)' % replay.MAX_SPEED)
    parser.add_argument('--side', help="puppet sides whose button 1 stops the replay; into "
                                       "the puppet, the arms played (default: the episode's)")
    parser.add_argument('--arms', help="Baxter arms to replay, e.g. right or left,right "
                                       "(default: those the episode commands)")
    parser.add_argument('--zones', metavar='FILE',
                        help="keep-out zone file the robot's arms keep out of (/dev/null: none; "
                             "default: the running arm controllers' zones_file, all of them "
                             "when arm_L's and arm_R's differ, else the package's "
                             "config/zones.yaml)")
    args = parser.parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    for given, what in ((args.arms, '--arms names Baxter arms'),
                        (args.zones, '--zones binds Baxter arms')):
        if given is not None and args.into == 'puppet':
            parser.error('%s: not with --into puppet' % what)

    def say(text):
        print('replay: %s' % text, file=sys.stderr, flush=True)
    try:
        bag_path, yaml_path = export_files.episode_paths(export_cli.resolve(args.episode))
        sides = parse_sides(args.side or ''.join(
            export_files.read_metadata(yaml_path).get('sides') or ifc.PUPPET_SIDES))
        say('reading %s' % bag_path)
        recording = export.collect(export_files.read_messages(bag_path, export.episode_topics()))
        if args.into == 'puppet':
            core = puppet_playback.PuppetPlayback(puppet_playback.puppet_paths(
                recording, sides), args.speed, 1.0 / puppet_player.RATE_HZ)
        else:
            arms = args.arms.replace(',', ' ').split() if args.arms else None
            limits = {s: baxter_description.arm_limits(s) for s in ifc.BAXTER_SIDES}
            paths, grips = replay.episode_script(recording, arms)
            replay.check_speed(args.speed)
    except (export_files.EpisodeError, ValueError) as error:
        say('failed: %s' % error)
        sys.exit(2)
    rospy.init_node('replay', anonymous=True)
    if args.into == 'robot':   # the zones' default comes from the parameter server
        try:
            guards = keepout_zones(args.zones, say)
        except ValueError as error:   # a bad zone file (ZoneFileError) or robot description
            say('refused: %s' % error)
            sys.exit(2)
        core = replay.Replay(paths, grips, limits, args.speed, 1.0 / RATE_HZ, guards=guards)
    node = (puppet_player.PuppetPlayer(core, say) if args.into == 'puppet'
            else ReplayNode(core, sides, say))
    sys.exit(node.run())
