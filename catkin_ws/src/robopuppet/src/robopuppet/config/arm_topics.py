"""config_X's topics besides its requests: the settings it publishes, opmode and teleop_state."""
import reprlib
import threading
import time

import rospy
from std_msgs.msg import String

from robopuppet import interface
from robopuppet.config import feel_profile
from robopuppet.config.follow_lock import TELEOP_STALE_S, FollowLock
from robopuppet_msgs.msg import ArmSettings, JointSettings, TeleopState


class ArmTopics:
    """Publish an arm's settings (latched), switch active_settings' profile on <ns>/opmode, and
    follow <ns>/teleop_state into a follow_lock.FollowLock.

    Args:
        ns: the arm's namespace, /puppet/arm_<side>.
        all_joints(): the stored (revision, [{name: value} of joint 0..6]) (SettingsKeeper's).
        lock: config_X's lock, held for every publish (so that they come in revision order) and
            around the follow lock.
        feel: {name: value} of the file's [feel] gains (feel_profile.feel_joint).
    See config_node.ConfigNode for the topics.
    """

    def __init__(self, ns, all_joints, lock, feel):
        self._ns, self._all_joints, self._lock, self._feel = ns, all_joints, lock, feel
        self._profile = ''  # of active_settings: '' or feel_profile.PROFILE
        self._stored_pub, self._active_pub = (
            rospy.Publisher('%s/%s' % (ns, topic), ArmSettings, queue_size=1, latch=True)
            for topic in (interface.STORED_SETTINGS, interface.ACTIVE_SETTINGS))
        self._follow_lock = FollowLock()   # only under the lock
        self._heard_teleop = threading.Event()
        self._subs = [rospy.Subscriber('%s/%s' % (ns, interface.OPMODE), String, self._on_opmode,
                                       queue_size=10),
                      rospy.Subscriber('%s/%s' % (ns, interface.TELEOP_STATE), TeleopState,
                                       self._on_teleop_state, queue_size=1)]

    def await_teleop_state(self):
        """Wait (at most TELEOP_STALE_S) for arm_X's latched teleop_state, if arm_X runs."""
        topic = '%s/%s' % (self._ns, interface.TELEOP_STATE)
        if (any(name == topic for name, _ in rospy.get_published_topics())
                and not self._heard_teleop.wait(TELEOP_STALE_S)):
            rospy.logwarn('%s: no %s within %g s: serving anyway', self._ns, topic,
                          TELEOP_STALE_S)

    def frozen(self, now_s):
        """Return why the angle settings may not change now, '' if they may (FollowLock.why);
        call with the lock held."""
        return self._follow_lock.why(now_s)

    def publish(self, stored=True):
        """Publish active_settings, and (if stored) stored_settings; call with the lock held."""
        revision, joints = self._all_joints()
        stamp = rospy.Time.now()
        for publisher, profile, values in (
                (self._stored_pub, '', joints),
                (self._active_pub, self._profile,
                 feel_profile.active_joints(self._profile, joints, self._feel)))[not stored:]:
            msg = ArmSettings(revision=revision, profile=profile, joints=[
                JointSettings(joint=joint, **v) for joint, v in enumerate(values)])
            msg.header.stamp = stamp
            publisher.publish(msg)

    def _on_opmode(self, msg):
        if msg.data not in interface.OPMODES:
            rospy.logwarn('%s: opmode must be one of %s, got %s; settings profile unchanged',
                          self._ns, '/'.join(interface.OPMODES), reprlib.repr(msg.data))
            return
        profile = feel_profile.PROFILE if msg.data == interface.FEEL else ''
        with self._lock:
            if profile == self._profile:
                return
            self._profile = profile
            self.publish(stored=False)
        rospy.loginfo('%s: opmode %s: active_settings are %s', self._ns, msg.data,
                      'the feel profile' if profile else 'the stored settings')

    def _on_teleop_state(self, msg):
        with self._lock:
            self._follow_lock.on_teleop_state(time.monotonic(), msg.follow_left,
                                              msg.follow_right)
        self._heard_teleop.set()
