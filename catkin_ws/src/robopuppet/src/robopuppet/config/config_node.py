"""config_X: keeps one puppet arm's ini file and serves its settings."""
import threading
import time

import rospkg
import rospy
from std_msgs.msg import Float32

from robopuppet import interface, settings
from robopuppet.config import config_file, config_store
from robopuppet_msgs.srv import GetConfig, GetConfigResponse


class ConfigNode:
    """Serve the arm's joint settings and persist every accepted change at once.

    Subscribes: <ns>/joint_J/<setting> (std_msgs/Float32) for J = 0..6 and the twelve settings
        of DESIGN section 5. A valid value is written to the file atomically; an invalid one
        (non-finite, a sign not +-1, outside the setting's bound in settings.SETTINGS, a minimum
        above its maximum) is refused with a warning and changes nothing. While the file cannot
        be written (read-only directory, full disk at start) every change is refused with an
        error saying that changes will not persist.
    Serves: <ns>/get_config (robopuppet_msgs/GetConfig): the twelve settings of a joint; a joint
        outside 0..6 is a service error naming the valid range.
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
        self._path = config_file.resolve_path(
            rospy.get_param('~file_name', 'arm_%s.ini' % side), rospkg.get_ros_home())
        self._lock = threading.Lock()
        stamp = time.strftime('%Y%m%d-%H%M%S')
        loaded = config_file.load_or_create(self._path, rospy.get_param('~seed_file', ''), stamp)
        self._config, self._text = loaded.config, loaded.text
        self._unwritable = loaded.unwritable  # why changes are refused, or ''
        for note in loaded.notes:
            rospy.loginfo(note)
        for problem in loaded.problems:
            rospy.logwarn(problem)
        if self._unwritable:
            rospy.logerr('%s: %s; serving what could be read (or the defaults), but CHANGES '
                         'WILL NOT PERSIST: every change is refused until the node restarts '
                         'with a writable file', self._ns, self._unwritable)
        self._subscribers = [
            rospy.Subscriber('%s/joint_%d/%s' % (self._ns, joint, name), Float32,
                             self._on_setting, callback_args=(joint, name), queue_size=100)
            for joint in settings.JOINTS for name in settings.NAMES]
        self._service = rospy.Service(self._ns + '/get_config', GetConfig, self._get_config)
        rospy.loginfo('serving %s/get_config from %s', self._ns, self._path)

    def _get_config(self, request):
        try:
            config_store.check_joint(request.joint)
        except config_store.InvalidSetting as error:
            raise rospy.ServiceException(str(error))
        with self._lock:
            values = self._config[request.joint]
            return GetConfigResponse(**values)

    def _on_setting(self, msg, key):
        joint, name = key
        with self._lock:
            if self._unwritable:
                rospy.logerr('%s: refused joint %d %s = %r: changes will not persist (%s); '
                             'settings unchanged', self._ns, joint, name, msg.data,
                             self._unwritable)
                return
            try:
                value = config_store.validate(self._config[joint], joint, name, msg.data)
            except config_store.InvalidSetting as error:
                rospy.logwarn('%s: refused %s; file and settings unchanged', self._ns, error)
                return
            if value == self._config[joint][name]:
                return
            new_config = {j: dict(v) for j, v in self._config.items()}
            new_config[joint][name] = value
            new_text = config_store.render(self._text, new_config, only={(joint, name)})
            try:
                config_file.write_atomic(self._path, new_text)
            except OSError as error:
                rospy.logerr('%s: refused joint %d %s = %r: could not save it to %s (%s), so it '
                             'would not persist; settings unchanged',
                             self._ns, joint, name, value, self._path, error)
                return
            self._config, self._text = new_config, new_text
        rospy.loginfo('joint %d %s = %s saved to %s', joint, name,
                      config_store.format_value(value), self._path)


def main():
    """Run the config node until shutdown."""
    rospy.init_node('config')
    try:
        ConfigNode()
    except (KeyError, ValueError, OSError) as error:
        rospy.logfatal('config node cannot start: %s', error)
        raise SystemExit(1)
    rospy.spin()
