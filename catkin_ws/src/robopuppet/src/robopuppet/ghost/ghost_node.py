"""ghost: publishes the ghost Baxter's joint states from the puppets' (ghost.ghost_pose maps)."""
import threading
import time

import rospkg
import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import JointState

from robopuppet import baxter_description, interface as ifc
from robopuppet.ghost import ghost_pose, ghost_urdf
from robopuppet.periodic import Guard, Loop
from robopuppet_msgs.msg import TeleopState


class GhostNode:
    """Feed the ghost's robot_state_publisher and pin the ghost's root to Baxter's base.

    Runs in the ghost's namespace (launch/ghost.launch: /ghost, and /target for the calibration
    target ghost), beside the robot_state_publisher that reads the ghost description
    (ghost_urdf) from robot_description there.

    ROS API (<ns>: interface.puppet_ns(X) for X in L, R):
      Subscribes: <ns>/joint_states (joint_0..joint_6, rad) and <ns>/teleop_state, or with
        ~target_topic only <ns>/<target_topic> (Baxter's joint names of the arm on X's side,
        rad: the calibration wizard's target); /robot/joint_states (the real robot: joints no
        puppet drives, arms without a puppet or target).
      Publishes: joint_states (relative: the ghost's, names prefixed) at ~rate, nothing while
        nothing is known; a static identity transform from base to <prefix>base on /tf_static.
      Parameters: ~prefix (str, 'ghost/', the ghost description's prefix), ~rate (Hz, 20),
        ~timeout (s, 0.5: a puppet or target silent this long no longer moves the ghost),
        ~target_topic (str, '': show the puppets; else show the targets on that topic).
    """

    def __init__(self):
        self._name = rospy.get_name()
        prefix = ghost_urdf.check_prefix(rospy.get_param('~prefix', ghost_urdf.DEFAULT_PREFIX))
        rate_hz, timeout_s = (float(rospy.get_param('~' + n, d))
                              for n, d in (('rate', 20.0), ('timeout', ifc.STOP_WITHIN_S)))
        if not (rate_hz > 0.0 and timeout_s > 0.0):
            raise ValueError('~rate and ~timeout must be positive, got %r, %r'
                             % (rate_hz, timeout_s))
        description = baxter_description.load(baxter_description.urdf_path(
            rospkg.RosPack().get_path('robopuppet')))
        movable = [j.name for j in description.joints.values() if j.velocity is not None]
        self._core = ghost_pose.GhostPose(
            {s: description.arm_limits(s) for s in ifc.BAXTER_SIDES}, movable, timeout_s, prefix)
        self._lock, self._guard = threading.Lock(), Guard(self._name, rospy.logerr)
        self._sources = None
        self._pub = rospy.Publisher('joint_states', JointState, queue_size=1)
        self._tf = tf2_ros.StaticTransformBroadcaster()
        pin = TransformStamped()
        pin.header.stamp = rospy.Time.now()
        pin.header.frame_id = baxter_description.BASE_FRAME
        pin.child_frame_id = prefix + baxter_description.BASE_FRAME
        pin.transform.rotation.w = 1.0
        self._tf.sendTransform(pin)
        target_topic = rospy.get_param('~target_topic', '')
        self._shows = 'calibration target' if target_topic else 'puppet'
        for side in ifc.PUPPET_SIDES:
            ns = ifc.puppet_ns(side) + '/'
            if target_topic:
                rospy.Subscriber(ns + target_topic, JointState, lambda m, s=side: self._take(
                    self._on_target, s, m), queue_size=10)
                continue
            rospy.Subscriber(ns + ifc.JOINT_STATES, JointState,
                             lambda m, s=side: self._take(self._on_puppet, s, m), queue_size=10)
            rospy.Subscriber(ns + ifc.TELEOP_STATE, TeleopState,
                             lambda m, s=side: self._take(self._on_teleop, s, m), queue_size=10)
        rospy.Subscriber(ifc.ROBOT_JOINT_STATES, JointState,
                         lambda m: self._take(self._on_robot, m), queue_size=1)
        self._loop = Loop(self._guard, 'publish loop', 1.0 / rate_hz, self._publish)
        self._loop.start()
        rospy.on_shutdown(self._loop.stop)

    def _take(self, handler, *args):
        """Run a subscriber callback under the lock and the guard."""
        with self._lock:
            self._guard.call(handler.__name__, handler, *args)

    def _warn(self, problem):
        if problem:
            rospy.logwarn_throttle(5, '%s: %s', self._name, problem)

    def _on_puppet(self, side, msg):
        self._warn(self._core.on_puppet(time.monotonic(), side, msg.name, msg.position))

    def _on_target(self, side, msg):
        self._warn(self._core.on_target(time.monotonic(), side, msg.name, msg.position))

    def _on_teleop(self, side, msg):
        self._core.on_teleop(side, msg.follow_left, msg.follow_right)

    def _on_robot(self, msg):
        self._warn(self._core.on_robot(msg.name, msg.position))

    def _publish(self):
        with self._lock:
            now = time.monotonic()
            sources = self._core.sources(now)
            names, positions = self._core.joint_states(now)
        if sources != self._sources:
            self._sources = sources
            rospy.loginfo('%s: %s', self._name, describe(sources, self._shows))
        if names:
            self._pub.publish(JointState(name=names, position=positions,
                                         header=rospy.Header(stamp=rospy.Time.now())))


def describe(sources, shows='puppet'):
    """Return a log line saying what each ghost arm shows, e.g. 'left arm: puppet R mirrored'
    (shows: what a source is, 'puppet' or 'calibration target')."""
    parts = []
    for arm, puppet in sorted(sources.items()):
        if puppet == ghost_pose.REAL:
            parts.append('%s arm: no live %s, shows the real arm' % (arm, shows))
        else:
            how = '' if ifc.BAXTER_SIDE[puppet] == arm else ' mirrored'
            parts.append('%s arm: %s %s%s' % (arm, shows, puppet, how))
    return '; '.join(parts)


def main():
    """Run the ghost node until shutdown."""
    rospy.init_node('ghost')
    GhostNode()
    rospy.spin()
