"""config_X: keeps one puppet arm's ini file, serves and publishes its settings."""
import threading
import time

import rospkg
import rospy
from std_msgs.msg import Float32

from robopuppet import atomic_file, interface, settings
from robopuppet.config import config_file, config_store
from robopuppet.config.arm_topics import ArmTopics
from robopuppet.config.settings_keeper import SettingsKeeper
from robopuppet_msgs.msg import ArmSettings, JointSettings
from robopuppet_msgs.srv import (GetConfig, GetConfigResponse, SetArmConfig,
                                 SetArmConfigResponse, SetConfig, SetConfigResponse)


class ConfigNode:
    """Own the arm's joint settings: store a change only once the file holds it, then publish.

    The node owns the file while it runs: edit it by hand only while the node is stopped. Its
    [feel] section (gain_scale, voltage_limit) is read at start only (defaults when missing). A
    damaged file (a bad [feel] value too) is backed up and repaired once at start. A file that
    cannot be read, or cannot be written although it must be repaired or created, leaves the
    node serving what it could read (or the defaults), refusing every change with that reason
    until it restarts. Every refusal is logged (an error when it is about persistence).

    Serves: <ns>/set_config (robopuppet_msgs/SetConfig): some settings of one joint, stored all
        or none (settings_keeper.SettingsKeeper.request: bounds, signs +-1, the ranges' rules
        after the whole request, the file written atomically; no change of what the puppet's
        angles mean, settings.ANGLE_SETTINGS, while <ns>/teleop_state says a Baxter arm follows:
        config.follow_lock); the answer holds what is stored now and, when refused, why.
        <ns>/set_arm_config (robopuppet_msgs/SetArmConfig): settings of several joints in one
        request (a calibration and its undo), checked as set_config's, stored all or none with
        one atomic replace of the file and one revision (request_arm); the answer holds all
        seven joints as stored now. <ns>/get_config (robopuppet_msgs/GetConfig): the twelve
        settings of a joint; a joint outside 0..6 is a service error naming the range.
    Publishes (config.arm_topics): <ns>/stored_settings (robopuppet_msgs/ArmSettings, latched):
        all seven joints, at start and after every change written to the file; revision counts
        those changes. <ns>/active_settings (robopuppet_msgs/ArmSettings, latched; serial_X
        loads it into the device): at the same moments and whenever the profile changes, the
        same revision; profile '' = the stored settings, 'feel' (while <ns>/opmode is feel) =
        those with the [feel] gains laid over them (feel_profile.feel_joint), never stored.
    Subscribes: <ns>/joint_J/<setting> (std_msgs/Float32), J = 0..6 and the twelve settings of
        settings.SETTINGS (the 2020 topics): each message is a one-setting set_config request.
        <ns>/opmode (std_msgs/String: limp, hold or feel): feel selects the feel profile, limp
        and hold the stored one; a repeat of the current mode changes nothing.
        <ns>/teleop_state (robopuppet_msgs/TeleopState, arm_X's, latched): whether an arm
        follows. While arm_X publishes it, the node serves nothing before it has heard it
        (at most follow_lock.TELEOP_STALE_S), so that a node respawned while an arm follows
        never takes a new home_angle in its first moments.
    Parameters:
        ~arm_side (str, required): 'L' or 'R'; <ns> is /puppet/arm_<side>.
        ~file_name (str, default 'arm_<side>.ini'): the live file; a relative path is taken
            under $ROS_HOME/robopuppet/ (ROS_HOME defaults to ~/.ros).
        ~seed_file (str, default ''): the file copied when the live file does not exist yet,
            normally the package's config/arm_<side>.ini.
    """

    def __init__(self):
        side = rospy.get_param('~arm_side')
        self._ns = interface.puppet_ns(side)
        self._path = path = config_file.resolve_path(
            rospy.get_param('~file_name', interface.ini_file_name(side)), rospkg.get_ros_home())
        loaded = config_file.load_or_create(path, rospy.get_param('~seed_file', ''),
                                            time.strftime('%Y%m%d-%H%M%S'))
        for note in loaded.notes:
            rospy.loginfo(note)
        for problem in loaded.problems:
            rospy.logwarn(problem)
        if loaded.unwritable:
            rospy.logerr('%s: %s; serving what could be read (or the defaults), but CHANGES '
                         'WILL NOT PERSIST: every change is refused until the node restarts '
                         'with a writable file', self._ns, loaded.unwritable)
        self._keeper = SettingsKeeper(loaded.config, loaded.text, loaded.unwritable, path,
                                      atomic_file.write_atomic)
        self._lock = threading.Lock()  # one request at a time; publishes in revision order
        feel = config_store.parse_feel(loaded.text)[0]
        rospy.loginfo('%s: feel mode gains from %s: %s', self._ns, path, ', '.join(
            '%s = %s' % (n, config_store.format_value(v)) for n, v in feel.items()))
        with self._lock:   # an opmode waits for the first publish
            self._topics = ArmTopics(self._ns, self._keeper.all_joints, self._lock, feel)
            self._topics.publish()
        self._subscribers = [
            rospy.Subscriber(interface.joint_topic(side, joint, name), Float32, self._on_setting,
                             callback_args=(joint, name), queue_size=100)
            for joint in settings.JOINTS for name in settings.NAMES]
        self._topics.await_teleop_state()
        self._services = [
            rospy.Service('%s/%s' % (self._ns, name), kind, handler) for name, kind, handler in (
                (interface.SET_CONFIG, SetConfig, self._set_config),
                (interface.SET_ARM_CONFIG, SetArmConfig, self._set_arm_config),
                (interface.GET_CONFIG, GetConfig, self._get_config))]
        rospy.loginfo('serving %s/%s, %s and %s from %s', self._ns, interface.GET_CONFIG,
                      interface.SET_CONFIG, interface.SET_ARM_CONFIG, path)

    def _get_config(self, request):
        with self._lock:
            try:
                return GetConfigResponse(**self._keeper.joint(request.joint))
            except config_store.InvalidSetting as error:
                raise rospy.ServiceException(str(error))

    def _set_config(self, request):
        answer = self._store([(request.joint, list(request.names), list(request.values))])[0]
        return SetConfigResponse(answer.stored, answer.error,
                                 JointSettings(joint=request.joint, **(answer.values or {})))

    def _set_arm_config(self, request):
        answer, revision = self._store([(change.joint, list(change.names), list(change.values))
                                        for change in request.joints], arm=True)
        return SetArmConfigResponse(answer.stored, answer.error, ArmSettings(
            revision=revision, joints=[JointSettings(joint=joint, **values)
                                       for joint, values in enumerate(answer.values)]))

    def _on_setting(self, msg, key):
        joint, name = key
        self._store([(joint, [name], [msg.data])])

    def _store(self, changes, arm=False):
        """Apply a request of [(joint, names, values)] (arm: request_arm's, else request's of
        its one joint), publish what is stored if it changed, log the outcome; return the
        Answer and the revision after it."""
        with self._lock:
            frozen = self._topics.frozen(time.monotonic())
            answer = (self._keeper.request_arm(changes, frozen) if arm
                      else self._keeper.request(*changes[0], frozen))
            revision = self._keeper.revision
            if answer.written:
                self._topics.publish()
        what = '; '.join('joint %d %s' % (joint, ', '.join(
            '%s = %r' % item for item in zip(names, values))) for joint, names, values in changes)
        if answer.written:
            rospy.loginfo('%s saved to %s (revision %d)', what, self._path, revision)
        elif answer.persistence:
            rospy.logerr('%s: refused %s: %s; settings unchanged', self._ns, what, answer.error)
        elif not answer.stored:
            rospy.logwarn('%s: refused %s; file and settings unchanged', self._ns, answer.error)
        return answer, revision


def main():
    """Run the config node until shutdown."""
    rospy.init_node('config')
    try:
        ConfigNode()
    except (KeyError, ValueError, OSError) as error:
        rospy.logfatal('config node cannot start: %s', error)
        raise SystemExit(1)
    rospy.spin()
