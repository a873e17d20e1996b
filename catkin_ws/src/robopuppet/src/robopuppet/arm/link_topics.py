"""arm_X's topics of the operator-robot link: pings out, echoes in, LinkState and its /diagnostics
status out. robopuppet.arm.controller (link_watch, link_clock) decides; this only wires topics.
"""
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from robopuppet import interface as ifc
from robopuppet.arm.link_clock import PING_PERIOD_S
from robopuppet.periodic import Loop
from robopuppet_msgs.msg import LinkPing, LinkState


def ros_now_s():
    """Return the robot host's ROS clock in seconds."""
    return rospy.Time.now().to_sec()


class LinkTopics:
    """Ping the operator host, take its echoes and publish the link's state; every controller
    call is made under the node's lock.

    Publishes <ns>/link_ping (robopuppet_msgs/LinkPing, 10 Hz, tcp_nodelay), <ns>/link_state
    (robopuppet_msgs/LinkState, 5 Hz) and /diagnostics (name 'arm_X: operator-robot link',
    hardware_id <ns>); subscribes <ns>/link_echo (tcp_nodelay: serial_X answers each ping at
    once with its own clock).

    Args:
        ns: the puppet's namespace, e.g. /puppet/arm_R.
        core: the node's controller.ArmController.
        lock: the node's lock, held for every call of core.
        guard: the node's robopuppet.periodic.Guard, for the link loop.
        name: the node's name for log lines (arm_X).
    """

    def __init__(self, ns, core, lock, guard, name):
        self._core, self._lock, self._name = core, lock, name
        self._ping = rospy.Publisher(ns + '/' + ifc.LINK_PING, LinkPing, queue_size=10,
                                     tcp_nodelay=True)
        self._state = rospy.Publisher(ns + '/' + ifc.LINK_STATE, LinkState, queue_size=10)
        self._diag = rospy.Publisher(ifc.DIAGNOSTICS, DiagnosticArray, queue_size=10)
        rospy.Subscriber(ns + '/' + ifc.LINK_ECHO, LinkPing, self._on_echo, queue_size=10,
                         tcp_nodelay=True)
        # Twice per ping period: the core paces the pings and the reports.
        self.loop = Loop(guard, 'link loop', PING_PERIOD_S / 2, lambda: self._tick(ros_now_s()))

    def _on_echo(self, msg):
        arrived_s = ros_now_s()   # before the lock: the wait for it is not the network's
        with self._lock:
            why = self._core.on_echo(arrived_s, msg.seq, msg.sent.to_sec(), msg.echoed.to_sec())
        if why:
            rospy.logwarn_throttle(5, '%s: %s', self._name, why)

    def _tick(self, now_s):
        with self._lock:
            ping = self._core.ping(now_s)
            if ping:
                seq, sent_s = ping
                self._ping.publish(LinkPing(seq=seq, sent=rospy.Time.from_sec(sent_s)))
            r = self._core.link_report(now_s)
            if r is not None:
                self._publish(r, now_s)

    def _publish(self, r, now_s):
        msg = LinkState(rtt=r.rtt_s, clock_offset=r.clock_offset_s, clock_known=r.clock_known,
                        sample_age=r.sample_age_s, max_sample_age=r.max_sample_age_s,
                        loss=r.loss, level=r.level, fault=r.fault, detail=r.detail)
        msg.header.stamp = rospy.Time.from_sec(now_s)
        self._state.publish(msg)
        self._diag.publish(DiagnosticArray(header=msg.header, status=[DiagnosticStatus(
            level=r.level, name=r.diag_name, message=r.message, hardware_id=r.hardware_id,
            values=[KeyValue(k, v) for k, v in r.values])]))
