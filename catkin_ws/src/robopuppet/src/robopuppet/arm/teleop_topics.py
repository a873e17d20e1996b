"""arm_X's teleop report: teleop_state, its /diagnostics status and the zone markers it highlights.

robopuppet.arm.controller decides the report (controller.Report); this only wires topics.
"""
import time

import rosgraph
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from robopuppet import interface as ifc
from robopuppet.arm import zone_topics
from robopuppet.link_recovery import answers
from robopuppet_msgs.msg import TeleopState


class TeleopTopics:
    """Publish the controller's reports, and a last one on shutdown.

    Publishes <ns>/teleop_state (robopuppet_msgs/TeleopState, latched; zone_left/zone_right name
    a zone holding an arm back, the detail its zone and link; assist_left/assist_right the arm
    the assist drives through arm_X), /diagnostics (name 'arm_X:
    teleoperation', hardware_id <ns>), interface.ZONE_MARKERS (/robopuppet/keepout_zones,
    visualization_msgs/MarkerArray, latched) and interface.ZONE_HOLD_MARKERS (the zones holding an
    arm back highlighted, on a change; arm.zone_topics).

    Args:
        ns: the puppet's namespace, e.g. /puppet/arm_R.
        found: the keep-out zones (world Shapes), published at once (zone_topics.publish_zones).
        name: the node's name for log lines (arm_X).
    """

    def __init__(self, ns, found, name):
        self._name, self._opmode = name, ''
        self._zone_view = zone_topics.publish_zones(found, name)
        self._state = rospy.Publisher(ns + '/' + ifc.TELEOP_STATE, TeleopState, queue_size=10,
                                      latch=True)
        self._diag = rospy.Publisher(ifc.DIAGNOSTICS, DiagnosticArray, queue_size=10)

    def publish(self, r):
        """Publish a controller.Report (log it if it changed); republish the zones held."""
        if r.changed:
            rospy.loginfo('%s: %s (%s)', self._name, r.state, r.detail)
        self._opmode = r.opmode
        msg = TeleopState(state=r.state, follow_left=r.follow_left, follow_right=r.follow_right,
                          opmode=r.opmode, heartbeat_age=r.heartbeat_age_s, detail=r.detail,
                          zone_left=r.zone_left, zone_right=r.zone_right,
                          assist_left=r.assist_left, assist_right=r.assist_right)
        msg.header.stamp = rospy.Time.now()
        self._state.publish(msg)
        self._zone_view.show(time.monotonic(), r.zone_left, r.zone_right)  # never raises
        self._diag.publish(DiagnosticArray(header=msg.header, status=[DiagnosticStatus(
            level=getattr(DiagnosticStatus, r.level), name=r.diag_name, message=r.message,
            hardware_id=r.hardware_id, values=[KeyValue(k, v) for k, v in r.values])]))

    def shut_down(self):
        """Tell the operator host why nothing follows any more: a last teleop_state (fault)
        and a log line; Baxter finishes its last position command (mode 1 has no command
        timeout) and stays there."""
        master_gone = not answers(rosgraph.get_master_uri())
        detail = ('%s stopped: %s; Baxter stops at its last command until %s runs again' % (
            self._name, 'the ROS master does not answer (roslaunch stops its nodes with it)'
            if master_gone else 'shut down', self._name))
        (rospy.logwarn if master_gone else rospy.loginfo)('%s', detail)
        msg = TeleopState(state=ifc.FAULT, opmode=self._opmode, detail=detail)
        msg.header.stamp = rospy.Time.now()
        self._state.publish(msg)
