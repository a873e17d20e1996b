"""The GUI's publishers of one puppet arm: its opmode and setpoints, the calibration target, a
replay's stop, the assist's stop and start."""
import math
import reprlib

import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, String

from robopuppet import interface, settings
from robopuppet.calibration import procedure


class CommandTopics:
    """Command one puppet arm (and ask a running replay to stop).

    Publishes (under <ns> = /puppet/arm_<side>): <ns>/opmode (std_msgs/String),
        <ns>/joint_J/setpoint (std_msgs/Float32), <ns>/calibration_target
        (sensor_msgs/JointState, interface.CALIBRATION_TARGET); interface.REPLAY_STOP
        (std_msgs/Empty) on stop_replay(); interface.ASSIST_COMMAND (std_msgs/String, 'stop' or
        'start') on command_assist().
    """

    def __init__(self, side, arm_state):
        self.side = side
        self.state = arm_state
        ns = interface.puppet_ns(side)
        self._opmode_pub = rospy.Publisher('%s/%s' % (ns, interface.OPMODE), String,
                                           queue_size=1)
        self._setpoint_pubs = [rospy.Publisher(interface.joint_topic(side, joint, 'setpoint'),
                                               Float32, queue_size=1)
                               for joint in settings.JOINTS]
        self._target_pub = rospy.Publisher('%s/%s' % (ns, interface.CALIBRATION_TARGET), JointState,
                                           queue_size=1)
        self._replay_stop_pub = rospy.Publisher(interface.REPLAY_STOP, Empty, queue_size=1)
        self._assist_pub = rospy.Publisher(interface.ASSIST_COMMAND, String, queue_size=1)

    def set_opmode(self, opmode):
        """Publish the opmode: limp, hold or feel.

        Hold and feel first send each joint's current angle as its setpoint: the firmware holds
        the setpoints it has (0 rad after limp), so a bare hold would drive the puppet to 0 rad
        (in feel, arm_X then streams Baxter's pose as setpoints).
        """
        if opmode not in interface.OPMODES:
            raise ValueError('opmode must be one of %s, got %s' % (interface.OPMODES,
                                                                   reprlib.repr(opmode)))
        if opmode in (interface.HOLD, interface.FEEL):
            for joint, values in enumerate(self.state.snapshot().joints):
                if math.isfinite(values.angle_rad):
                    self.set_setpoint(joint, values.angle_rad)
        self._opmode_pub.publish(String(opmode))

    def set_setpoint(self, joint, angle_rad):
        """Publish a joint's setpoint (rad; used by the puppet in hold mode)."""
        self._setpoint_pubs[joint].publish(Float32(angle_rad))

    def publish_target(self, pose):
        """Publish a procedure.Pose as the calibration target (Baxter's names and rad)."""
        names, positions = procedure.target_state(self.side, pose)
        self._target_pub.publish(JointState(name=names, position=positions,
                                            header=rospy.Header(stamp=rospy.Time.now())))

    def stop_replay(self):
        """Ask a running replay to stop (std_msgs/Empty on interface.REPLAY_STOP)."""
        self._replay_stop_pub.publish(Empty())

    def command_assist(self, command):
        """Ask the assist node to stop or start (interface.ASSIST_COMMANDS) driving its arm."""
        if command not in interface.ASSIST_COMMANDS:
            raise ValueError('assist command must be one of %s, got %s' % (
                interface.ASSIST_COMMANDS, reprlib.repr(command)))
        self._assist_pub.publish(String(command))
