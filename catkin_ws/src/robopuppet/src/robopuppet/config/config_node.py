"""config_X: keeps one puppet arm's ini file, serves and publishes its settings."""
import threading
import time

import rospkg
import rospy
from std_msgs.msg import Float32

from robopuppet import interface, settings
from robopuppet.config import config_file, config_store
from robopuppet.config.settings_keeper import SettingsKeeper
from robopuppet_msgs.msg import ArmSettings, JointSettings
from robopuppet_msgs.srv import GetConfig, GetConfigResponse, SetConfig, SetConfigResponse


class ConfigNode:
    """Own the arm's joint settings: store a change only once the file holds it, then publish.

    Serves: <ns>/set_config (robopuppet_msgs/SetConfig): some settings of one joint, stored all
        or none (settings_keeper.SettingsKeeper.request: bounds, signs +-1, each minimum <= its
        maximum after the whole request, the file written atomically); the answer holds what
        is stored now and, when refused, why. <ns>/get_config (robopuppet_msgs/GetConfig): the
        twelve settings of a joint; a joint outside 0..6 is a service error naming the range.
    Publishes: <ns>/stored_settings (robopuppet_msgs/ArmSettings, latched): all seven joints,
        at start and after every change written to the file; revision counts those changes.
    Subscribes: <ns>/joint_J/<setting> (std_msgs/Float32), J = 0..6 and the twelve settings of
        settings.SETTINGS (the 2020 topics): each message is a one-setting set_config request.
    Every refusal is logged: a warning for a refused value, an error when the change would not
    persist. While the file cannot be written (read-only directory, full disk at start) every
    request is refused with that reason.
    Parameters:
        ~arm_side (str, required): 'L' or 'R'; <ns> is /puppet/arm_<side>.
        ~file_name (str, default 'arm_<side>.ini'): the live file; a relative path is taken
            under $ROS_HOME/robopuppet/ (ROS_HOME defaults to ~/.ros).
        ~seed_file (str, default ''): the file copied when the live file does not exist yet,
            normally the package's config/arm_<side>.ini.
    The node owns the file while it runs: edit it by hand only while the node is stopped.
    A damaged file is backed up and repaired once at start. A file that cannot be read, or cannot
    be written although it must be repaired or created, leaves the node serving what it could
    read (or the defaults), refusing every change, until it is restarted.
    """

    def __init__(self):
        side = rospy.get_param('~arm_side')
        self._ns = interface.puppet_ns(side)
        path = config_file.resolve_path(
            rospy.get_param('~file_name', 'arm_%s.ini' % side), rospkg.get_ros_home())
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
        self._path = path
        self._keeper = SettingsKeeper(loaded.config, loaded.text, loaded.unwritable, path,
                                      config_file.write_atomic)
        self._lock = threading.Lock()  # one request at a time; publishes in revision order
        self._stored_pub = rospy.Publisher('%s/%s' % (self._ns, interface.STORED_SETTINGS),
                                           ArmSettings, queue_size=1, latch=True)
        with self._lock:
            self._publish()
        self._subscribers = [
            rospy.Subscriber(interface.joint_topic(side, joint, name), Float32, self._on_setting,
                             callback_args=(joint, name), queue_size=100)
            for joint in settings.JOINTS for name in settings.NAMES]
        self._services = [
            rospy.Service('%s/%s' % (self._ns, interface.SET_CONFIG), SetConfig,
                          self._set_config),
            rospy.Service('%s/%s' % (self._ns, interface.GET_CONFIG), GetConfig,
                          self._get_config)]
        rospy.loginfo('serving %s/%s and %s/%s from %s', self._ns, interface.GET_CONFIG,
                      self._ns, interface.SET_CONFIG, path)

    def _get_config(self, request):
        with self._lock:
            try:
                return GetConfigResponse(**self._keeper.joint(request.joint))
            except config_store.InvalidSetting as error:
                raise rospy.ServiceException(str(error))

    def _set_config(self, request):
        answer = self._store(request.joint, list(request.names), list(request.values))
        return SetConfigResponse(answer.stored, answer.error,
                                 JointSettings(joint=request.joint, **(answer.values or {})))

    def _on_setting(self, msg, key):
        joint, name = key
        self._store(joint, [name], [msg.data])

    def _store(self, joint, names, values):
        """Apply a request, publish what is stored if it changed, log the outcome."""
        with self._lock:
            answer = self._keeper.request(joint, names, values)
            revision = self._keeper.revision
            if answer.written:
                self._publish()
        what = ', '.join('%s = %r' % item for item in zip(names, values))
        if answer.written:
            rospy.loginfo('joint %d %s saved to %s (revision %d)', joint, what, self._path,
                          revision)
        elif answer.persistence:
            rospy.logerr('%s: refused joint %d %s: %s; settings unchanged', self._ns, joint,
                         what, answer.error)
        elif not answer.stored:
            rospy.logwarn('%s: refused %s; file and settings unchanged', self._ns, answer.error)
        return answer

    def _publish(self):
        """Publish all stored settings; call with the lock held."""
        revision, joints = self._keeper.all_joints()
        msg = ArmSettings(revision=revision, joints=[
            JointSettings(joint=joint, **values) for joint, values in enumerate(joints)])
        msg.header.stamp = rospy.Time.now()
        self._stored_pub.publish(msg)


def main():
    """Run the config node until shutdown."""
    rospy.init_node('config')
    try:
        ConfigNode()
    except (KeyError, ValueError, OSError) as error:
        rospy.logfatal('config node cannot start: %s', error)
        raise SystemExit(1)
    rospy.spin()
