"""arm_X's command loop and its watchdog: when the arm controller steps, and where its actions go.

robopuppet.arm.controller decides; this steps it under the node's lock at least once per command
period and on demand, publishes its actions (the table action -> publisher; topics in ArmNode's
ROS API), and faults a loop that completes no step.
"""
import functools
import time

import rospy
from baxter_core_msgs.msg import EndEffectorCommand, JointCommand
from std_msgs.msg import Bool, Float32, String

from robopuppet import interface as ifc, settings
from robopuppet.arm import baxter_upkeep, controller, opmode
from robopuppet.periodic import Loop

WATCHDOG_PERIOD_S = 0.05     # the watchdog thread checks the command loop this often


class CommandLoop:
    """Step the controller on a loop at twice the command rate when a step is due; watch it.

    Args:
        side: the puppet's side, 'L' or 'R'.
        core: the node's controller.ArmController.
        lock: the node's lock, held for every call of core.
        guard: the node's robopuppet.periodic.Guard (a failed step is logged and counted).
        period_s: the command period (s).
        report(controller.Report): publishes the teleop report (teleop_topics.TeleopTopics).
        name: the node's name for log lines (arm_X).
    Attributes:
        loops: the command loop and its watchdog (robopuppet.periodic.Loop), to start and stop.
    """

    def __init__(self, side, core, lock, guard, period_s, report, name):
        self._core, self._lock, self._name, self._period_s = core, lock, name, period_s
        pub = functools.partial(rospy.Publisher, queue_size=10)
        arm = {s: pub(ifc.limb_topic(s, 'joint_command'), JointCommand, tcp_nodelay=True)
               for s in ifc.BAXTER_SIDES}
        gripper = {s: pub(ifc.baxter_gripper_topic(s, 'command'), EndEffectorCommand)
                   for s in ifc.BAXTER_SIDES}
        enable = pub(ifc.SET_SUPER_ENABLE, Bool)
        mode = pub(ifc.puppet_ns(side) + '/' + ifc.OPMODE, String)
        setpoints = [pub(ifc.joint_topic(side, j, 'setpoint'), Float32) for j in settings.JOINTS]
        self._do = {  # action -> how it goes out
            controller.Enable: lambda a: enable.publish(Bool(True)),
            controller.ArmCommand: lambda a: arm[a.side].publish(JointCommand(
                mode=JointCommand.POSITION_MODE, command=a.angles, names=a.names)),
            opmode.SetOpmode: lambda a: mode.publish(String(a.mode)),
            opmode.SetSetpoints: lambda a: [p.publish(Float32(angle))
                                            for p, angle in zip(setpoints, a.angles)],
            baxter_upkeep.GripperCommand: lambda a: gripper[a.side].publish(EndEffectorCommand(
                id=a.id, command=a.command, args=a.args, sender=rospy.get_name(),
                sequence=a.sequence)),
            controller.Report: report}
        self.loops = [Loop(guard, 'command loop', period_s / 2, self._tick),
                      Loop(guard, 'watchdog', WATCHDOG_PERIOD_S, self._watch)]

    def carry_out(self, action):
        """Publish one of the controller's actions."""
        self._do[type(action)](action)

    def step(self, now):
        """Run one step at now (monotonic s) and carry it out, the lock held; a failure is
        raised and faults the next step."""
        try:
            for action in self._core.step(now):
                self.carry_out(action)
        except Exception as error:
            self._core.failed(error)
            raise
        self._core.done(now)

    def _tick(self):
        with self._lock:
            now = time.monotonic()
            if self._core.step_due(now):
                self.step(now)

    def _watch(self):
        """Fault the teleop when the command loop has not completed a step for a while."""
        wait_s = controller.STALL_PERIODS * self._period_s
        if not self._lock.acquire(timeout=wait_s):   # starved or stuck: the stall is faulted
            rospy.logerr_throttle(5, '%s: the command loop holds its lock for over %.2f s',
                                  self._name, wait_s)   # once it lets go (core.stall)
            return
        try:
            why = self._core.stall(time.monotonic())
            if why:
                rospy.logerr_throttle(5, '%s: command loop failed: %s', self._name, why)
                self.step(time.monotonic())
        finally:
            self._lock.release()
