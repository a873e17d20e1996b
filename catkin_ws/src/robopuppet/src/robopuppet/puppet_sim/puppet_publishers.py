"""The puppet_sim node's publishers: a puppet_device.Step as messages for tests and the GUI.

A ROS adapter beside puppet_sim_node: it builds messages and publishes them, and decides nothing.
"""
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, Header, MultiArrayDimension, MultiArrayLayout, String

from robopuppet import interface, settings
from robopuppet.puppet_sim.puppet_device import CONFIG_DIMS


class StepPublishers:
    """Publish what a device step leads to, on the simulator's topics below namespace `ns`.

    Publishes (the node's docstring has the contents): <ns>/device_config and
    <ns>/device_opmode (latched), <ns>/control, <ns>/hand_torque.
    """

    def __init__(self, ns):
        def publisher(name, kind, queue_size, latch=False):
            return rospy.Publisher('%s/%s' % (ns, name), kind, queue_size=queue_size, latch=latch)
        self.config = publisher(interface.SIM_DEVICE_CONFIG, Float32MultiArray, 1, latch=True)
        self.opmode = publisher(interface.SIM_DEVICE_OPMODE, String, 1, latch=True)
        self.control = publisher(interface.SIM_CONTROL, JointState, 100)
        self.hand_torque = publisher(interface.SIM_HAND_TORQUE, JointState, 10)

    def publish(self, step):
        """Publish a puppet_device.Step's settings, opmode, control ticks and hand torques."""
        if step.config is not None:
            self.config.publish(Float32MultiArray(MultiArrayLayout(
                [MultiArrayDimension(*dim) for dim in CONFIG_DIMS], 0), list(step.config)))
        if step.opmode is not None:
            self.opmode.publish(String(step.opmode))
        for tick in step.ticks:
            self.control.publish(JointState(
                Header(stamp=rospy.Time.now()), list(settings.JOINT_NAMES),
                list(tick.setpoint_rad), list(tick.angle_rad), list(tick.voltage_v)))
        if step.hand_torque is not None:
            self.hand_torque.publish(JointState(
                header=Header(stamp=rospy.Time.now()), name=list(settings.JOINT_NAMES),
                effort=list(step.hand_torque)))
