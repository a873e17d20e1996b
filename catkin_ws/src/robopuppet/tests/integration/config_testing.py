"""What the config node's rostests share: the fixture, starting and stopping config_R, its
services, and a listener to stored_settings (or active_settings)."""
import os
import re
import threading
import time

import roslaunch
import rospkg
import rospy

from robopuppet import interface, settings
from robopuppet_msgs.msg import ArmSettings
from robopuppet_msgs.srv import GetConfig, SetConfig

from waiting import wait_for

FIXTURE = os.path.join(rospkg.RosPack().get_path('robopuppet'),
                       'tests', 'integration', 'fixtures', 'arm_distinct.ini')
NS = interface.puppet_ns('R')
SERVICE = '%s/%s' % (NS, interface.GET_CONFIG)
SET_SERVICE = '%s/%s' % (NS, interface.SET_CONFIG)
STORED = '%s/%s' % (NS, interface.STORED_SETTINGS)
ACTIVE = '%s/%s' % (NS, interface.ACTIVE_SETTINGS)
LOG_LINE = re.compile(r'^\[rosout\]\[(\w+)\] \S+ \S+: (.*)$')  # the node's own log file


def joint_values(joint_settings):
    """Return {name: value} of a robopuppet_msgs/JointSettings (or a GetConfig response)."""
    return {name: getattr(joint_settings, name) for name in settings.NAMES}


def set_config(joint, **values):
    """Call config_R's set_config with {name: value}; return the response."""
    rospy.wait_for_service(SET_SERVICE, timeout=20)
    names = sorted(values)
    return rospy.ServiceProxy(SET_SERVICE, SetConfig)(joint, names,
                                                      [values[n] for n in names])


class StoredSettings:
    """Every robopuppet_msgs/ArmSettings received on config_R's stored_settings (or another
    topic, e.g. ACTIVE), in order."""

    def __init__(self, topic=STORED):
        self._lock = threading.Lock()
        self._messages = []
        self._subscriber = rospy.Subscriber(topic, ArmSettings, self._on_message)

    def _on_message(self, msg):
        with self._lock:
            self._messages.append(msg)

    def messages(self):
        """Return the messages received so far."""
        with self._lock:
            return list(self._messages)

    def wait(self, revision, timeout_s=10.0):
        """Return the first message of `revision` received within timeout_s, or None."""
        return wait_for(lambda: next((m for m in self.messages() if m.revision == revision),
                                     None), timeout_s)

    def unregister(self):
        self._subscriber.unregister()


class ConfigNodeRunner:
    """A unittest.TestCase mixin: start config_R on a file with self.launch, stop it again,
    read its log.

    Sets self.process (the running node or None) and self.log_file (its log file).
    """

    def start_node(self, path, seed=FIXTURE):
        """Start config_R on the live file `path`; return a get_config proxy once it serves."""
        node = roslaunch.core.Node(
            'robopuppet', 'config', name='config_R', output='screen',
            args='_arm_side:=R _file_name:=%s _seed_file:=%s' % (path, seed))
        self.process = self.launch.launch(node)
        self.log_file = [arg.split(':=', 1)[1] for arg in self.process.args
                         if arg.startswith('__log:=')][0]
        rospy.wait_for_service(SERVICE, timeout=20)
        return rospy.ServiceProxy(SERVICE, GetConfig)

    def stop_node(self):
        """Stop config_R and wait until get_config is gone."""
        self.process.stop()
        self.process = None
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            try:
                rospy.wait_for_service(SERVICE, timeout=0.2)
            except rospy.ROSException:
                return
        self.fail('config node did not stop')

    def logs(self):
        """Return [(level, message)] the running node logged so far (its rospy log file: the
        lines of its first moments never reach a /rosout subscriber that connects later)."""
        try:
            with open(self.log_file, errors='replace') as log:
                return [match.groups() for match in map(LOG_LINE.match, log) if match]
        except FileNotFoundError:
            return []

    def wait_log(self, level, text):
        """Return the messages of `level` ('INFO', 'WARNING', 'ERROR') that contain text, once
        there is one; fail when none came within 10 s."""
        found = wait_for(lambda: [msg for lvl, msg in self.logs()
                                  if lvl == level and text in msg], 10.0)
        self.assertTrue(found, 'no log %r in %r' % (text, self.logs()))
        return found
