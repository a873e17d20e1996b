"""The GUI's ROS client of one puppet arm: its state (gui.state_topics), its commands
(gui.command_topics), the config node's and the recorder's services; and the simulated puppet's.

No Qt here: the service calls block, so the GUI makes them off its thread.
"""
import collections

import rospkg
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, UInt8

from robopuppet import interface, settings
from robopuppet.episodes import recording
from robopuppet.gui.assist_topics import AssistTopics
from robopuppet.gui.command_topics import CommandTopics
from robopuppet.gui.state_topics import StateTopics
from robopuppet_msgs.msg import JointChange
from robopuppet_msgs.srv import GetConfig, Record, SetArmConfig, SetConfig

SetAnswer = collections.namedtuple('SetAnswer', 'stored error values')
SetAnswer.__doc__ = """The config node's answer to set_config: stored (bool), error (why not, or
'') and values, the joint's {name: value} stored now (set_arm_config's: {joint: {name: value}}
of all seven joints)."""


class ConfigUnavailable(RuntimeError):
    """get_config, set_config or set_arm_config did not answer (config node not running, or the
    call failed)."""


RecordAnswer = collections.namedtuple('RecordAnswer', 'ok error episode')
RecordAnswer.__doc__ = """The recorder's answer to /puppet/record: ok (bool), error (why not, or
''), episode (the episode's bag file)."""


class PuppetClient(StateTopics, CommandTopics, AssistTopics):
    """Connect an ArmState to one puppet arm's topics and services, one object for the widgets:
    its state (StateTopics), commands (CommandTopics), the assist's (AssistTopics), services:

    Calls: <ns>/get_config (robopuppet_msgs/GetConfig), <ns>/set_config
        (robopuppet_msgs/SetConfig), <ns>/set_arm_config (robopuppet_msgs/SetArmConfig),
        /puppet/record (robopuppet_msgs/Record).
    """

    def __init__(self, side, arm_state, clock=rospy.get_time):
        StateTopics.__init__(self, side, arm_state, clock)
        CommandTopics.__init__(self, side, arm_state)
        AssistTopics.__init__(self, clock)
        self._get_config = rospy.ServiceProxy(self._own(interface.GET_CONFIG), GetConfig)
        self._set_config = rospy.ServiceProxy(self._own(interface.SET_CONFIG), SetConfig)
        self._set_arm_config = rospy.ServiceProxy(self._own(interface.SET_ARM_CONFIG),
                                                  SetArmConfig)
        self._record = rospy.ServiceProxy(interface.RECORD_SERVICE, Record)

    def _own(self, name):
        return '%s/%s' % (self.ns, name)

    def now(self):
        """Return the current ROS time in s (the time base of the ArmState)."""
        return self._clock()

    @staticmethod
    def episodes_dir():
        """Return the recorder's default episodes directory ($ROS_HOME/robopuppet/episodes)."""
        return recording.episodes_dir(rospkg.get_ros_home())

    def get_config(self, joint, timeout_s=1.0):
        """Return the stored {name: value} of a joint. Blocks: call it off the GUI thread.

        Only finding the service is bounded (timeout_s); a config node that accepts the call and
        never answers blocks the caller, so the GUI gives up on its own deadline (JointTab).
        Raises ConfigUnavailable: the service is not there within timeout_s or the call failed.
        """
        response = self._call(self._get_config, self._own(interface.GET_CONFIG), timeout_s,
                              joint)
        return {name: getattr(response, name) for name in settings.NAMES}

    def set_config(self, joint, values, timeout_s=1.0):
        """Ask the config node to store {name: value} of a joint, all or none; return a
        SetAnswer. Blocks and raises like get_config."""
        names = list(values)
        response = self._call(self._set_config, self._own(interface.SET_CONFIG), timeout_s,
                              joint, names, [values[name] for name in names])
        return SetAnswer(response.stored, response.error,
                         {name: getattr(response.settings, name) for name in settings.NAMES})

    def set_arm_config(self, values, timeout_s=1.0):
        """Ask the config node to store {joint: {name: value}} in one request, all or none (a
        calibration); return a SetAnswer. Blocks and raises like get_config."""
        response = self._call(self._set_arm_config, self._own(interface.SET_ARM_CONFIG),
                              timeout_s, [JointChange(joint, list(v), list(v.values()))
                                          for joint, v in values.items()])
        return SetAnswer(response.stored, response.error, {
            j.joint: {name: getattr(j, name) for name in settings.NAMES}
            for j in response.settings.joints})

    def record(self, start, notes='', task='', timeout_s=1.0):
        """Ask the recorder to start (start True) or stop an episode; return a RecordAnswer.
        task: what a started episode demonstrates ('': the recorder's ~task). Blocks and
        raises (the recorder not there) like get_config."""
        response = self._call(self._record, interface.RECORD_SERVICE, timeout_s, start, notes,
                              task)
        return RecordAnswer(response.ok, response.error, response.episode)

    @staticmethod
    def _call(proxy, service, timeout_s, *args):
        try:
            proxy.wait_for_service(timeout_s)
            return proxy(*args)
        except (rospy.ROSException, rospy.ServiceException) as error:
            raise ConfigUnavailable('%s: %s' % (service, error)) from None


class SimPuppetClient:
    """Operate the simulated puppet: move its hand, hold its buttons.

    Publishes (latched, under /puppet_sim/arm_<side>): hand (sensor_msgs/JointState, joint_0..6
        in rad), button (std_msgs/UInt8, the button held down, 0 none), grippers
        (std_msgs/Float32MultiArray, four readings 0-1; reading 3 is the end-piece button,
        1 released, 0 pressed).
    """

    def __init__(self, side):
        self.ns = interface.sim_ns(side)
        self._hand_pub = rospy.Publisher('%s/%s' % (self.ns, interface.SIM_HAND), JointState,
                                         queue_size=1, latch=True)
        self._button_pub = rospy.Publisher('%s/%s' % (self.ns, interface.SIM_BUTTON), UInt8,
                                           queue_size=4, latch=True)
        self._grippers_pub = rospy.Publisher('%s/%s' % (self.ns, interface.SIM_GRIPPERS),
                                             Float32MultiArray, queue_size=4, latch=True)

    def connected(self):
        """Return True when a simulated puppet listens to the hand, button and grippers."""
        return all(p.get_num_connections() > 0
                   for p in (self._hand_pub, self._button_pub, self._grippers_pub))

    def set_hand(self, angles_rad):
        """Publish the seven hand angles (rad)."""
        msg = JointState(name=list(settings.JOINT_NAMES), position=[float(a) for a in angles_rad])
        msg.header.stamp = rospy.Time.now()
        self._hand_pub.publish(msg)

    def set_button(self, button):
        """Publish the button held down (1-4, 0 none)."""
        self._button_pub.publish(UInt8(button))

    def set_grippers(self, readings):
        """Publish the four gripper readings (0-1)."""
        self._grippers_pub.publish(Float32MultiArray(data=[float(r) for r in readings]))
