"""serial_X's publishers: the core's outputs, opmode and diagnostics as messages; the ping echo."""
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, String, UInt8

from robopuppet import interface, settings
from robopuppet.protocol import state_output as out
from robopuppet_msgs.msg import LinkPing


class SerialTopics:
    """Publish what serial_X's core hands on, in <ns> = /puppet/arm_<side> (see serial_node)."""

    def __init__(self, side, node_name):
        self._ns, self._name = interface.puppet_ns(side), node_name
        ns, joints = self._ns + '/', settings.JOINTS

        def pubs(kind, *topics):
            return [rospy.Publisher(topic, kind, queue_size=50) for topic in topics]
        heartbeat, self._states, button = (pubs(kind, ns + name)[0] for name, kind in (
            (interface.HEARTBEAT, Empty), (interface.JOINT_STATES, JointState),
            (interface.USER_BUTTON, UInt8)))
        angle, voltage, stat = (pubs(kind, *(interface.joint_topic(side, j, name) for j in joints))
                                for name, kind in (('angle', Float32), ('voltage', Float32),
                                                   ('enc_stat', String)))
        grippers = pubs(Float32, *(interface.gripper_topic(side, g)
                                   for g in range(interface.NUM_GRIPPERS)))
        self._diagnostics = rospy.Publisher(interface.DIAGNOSTICS, DiagnosticArray, queue_size=10)
        self._opmode = rospy.Publisher(ns + interface.OPMODE, String, queue_size=10)

        def each(publishers, kind, values):
            for publisher, value in zip(publishers, values):
                publisher.publish(kind(value))
        self._publish = {
            out.Heartbeat: lambda o: heartbeat.publish(Empty()), out.JointStates: self._joints,
            out.EncStatus: lambda o: stat[o.joint].publish(String(o.status)),
            out.JointTopics: lambda o: (each(angle, Float32, o.angles), each(
                voltage, Float32, o.voltages), each(stat, String, o.statuses)),
            out.Button: lambda o: button.publish(UInt8(o.button)),
            out.Grippers: lambda o: each(grippers, Float32, o.readings)}
        echo = rospy.Publisher(ns + interface.LINK_ECHO, LinkPing, queue_size=10,
                               tcp_nodelay=True)
        self._ping_sub = rospy.Subscriber(ns + interface.LINK_PING, LinkPing, lambda msg: (
            echo.publish(LinkPing(seq=msg.seq, sent=msg.sent, echoed=rospy.Time.now()))),
            queue_size=10, tcp_nodelay=True)

    def publish(self, outputs):
        """Publish the core's outputs (robopuppet.protocol.state_output), in order."""
        for output in outputs:
            self._publish[type(output)](output)

    def _joints(self, output):
        msg = JointState(name=settings.JOINT_NAMES, position=output.positions,
                         effort=output.efforts)
        msg.header.stamp = rospy.Time.now()
        msg.header.frame_id = output.angle_tag   # the angle settings: see arm.angle_settings
        self._states.publish(msg)

    def publish_opmode(self, mode):
        """Publish a mode on <ns>/opmode."""
        self._opmode.publish(String(mode))

    def publish_diagnostics(self, diagnostics):
        """Publish a link_health.Diagnostics on /diagnostics as '<node>: puppet serial link'."""
        level, message, values = diagnostics
        array = DiagnosticArray(status=[DiagnosticStatus(
            level=level, name='%s: %s' % (self._name, interface.DIAG_LINK), message=message,
            hardware_id=self._ns, values=[KeyValue(k, v) for k, v in values])])
        array.header.stamp = rospy.Time.now()
        self._diagnostics.publish(array)
