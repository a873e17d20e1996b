"""The calibrate command's view of one puppet arm over ROS: its readings and stored settings,
the calibration target for RViz, the simulated puppet's hand, and the one store request.
"""
import threading

import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32, String

from robopuppet import interface, settings
from robopuppet.calibration import procedure
from robopuppet_msgs.msg import ArmSettings, JointChange
from robopuppet_msgs.srv import SetArmConfig

WAIT_S = 10.0  # for the arm's readings, stored settings and set_arm_config service


class ArmReader:
    """Keep the latest encoder statuses, angles and stored settings of one puppet arm.

    Subscribes (under /puppet/arm_<side>): joint_J/enc_stat, joint_J/angle, stored_settings.
    Calls: set_arm_config (robopuppet_msgs/SetArmConfig).
    Publishes: calibration_target (sensor_msgs/JointState, interface.CALIBRATION_TARGET) at
        procedure.TARGET_RATE_HZ while show_target has a pose, nothing otherwise;
        /puppet_sim/arm_<side>/hand (sensor_msgs/JointState, latched) on pose_sim only.
    """

    def __init__(self, side):
        self._lock = threading.Lock()
        self._readings = [(None, float('nan'))] * settings.NUM_JOINTS
        self._stored = None
        self.side, self._target = side, None
        ns = interface.puppet_ns(side)
        self._target_pub = rospy.Publisher('%s/%s' % (ns, interface.CALIBRATION_TARGET), JointState,
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
