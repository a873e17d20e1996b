"""The ROS side of playback onto the robot (`replay EPISODE`, the default): feeds
robopuppet.episodes.replay what Baxter and the watched puppet sides report and sends its
commands through Baxter's own API (the stand-in's too).

Used by robopuppet.episodes.replay_node (the terminal command replay), which reads the episode
and builds the core.
"""
import json
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
from robopuppet.episodes import replay
from robopuppet.episodes.player import Player
from robopuppet_msgs.msg import TeleopState

RATE_HZ = 100.0
WAIT_S = 5.0        # for Baxter's state and pose before refusing


def keepout_zones(given, say):
    """Return {Baxter side: ZoneGuard} ({} when every file is '') of the zones a replay onto the
    robot keeps the arms out of, and say which: the file given (replay's and move_arms'
    --zones), else the running arm controllers' zone files, else the package's.

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


class RobotPlayer(Player):
    """Replay one episode; run() returns the exit code.

    Subscribes: /robot/state, /robot/joint_states, Baxter's gripper states, and per watched
    puppet side user_btn, joint_states and teleop_state; interface.REPLAY_STOP (Empty).
    Publishes: /robot/limb/<side>/joint_command (POSITION_MODE, RATE_HZ) and
    /robot/end_effector/<side>_gripper/command ('go') of the replayed arms.
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
