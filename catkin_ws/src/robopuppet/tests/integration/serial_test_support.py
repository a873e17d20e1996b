"""Shared helpers of the serial integration tests (serial_*_test.py)."""
import os
import shutil
import tempfile
import threading
import time

import rosgraph
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from roslaunch.core import Node
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, String

from robopuppet import interface, settings
from robopuppet.config import config_store
from robopuppet_msgs.msg import ArmSettings, JointSettings

from waiting import wait_for

SIM = interface.sim_ns('L')
NS = interface.puppet_ns('L')
PER_JOINT = len(settings.NAMES)


def topic(name, ns=NS):
    """Return a topic of serial_L's arm (or, with ns=SIM, of the simulated puppet)."""
    return '%s/%s' % (ns, name)


def seed_values(path):
    """Return the 84 settings of an ini file, joint-major in settings.NAMES order."""
    with open(path) as ini:
        config, problems = config_store.parse(ini.read())
    assert not problems, problems
    return [config[j][n] for j in settings.JOINTS for n in settings.NAMES]


def index(joint, name):
    """Return the place of a joint's setting in a list of 84 values (seed_values' order)."""
    return joint * PER_JOINT + settings.CONFIG_ID[name]


class ActiveSettings:
    """Stands in for config_X: publishes 84 values as latched active_settings revisions."""

    def __init__(self):
        self.revision = 0
        self.publisher = rospy.Publisher(topic(interface.ACTIVE_SETTINGS), ArmSettings,
                                         queue_size=10, latch=True)

    def publish(self, values):
        """Publish values (84, joint-major) as the next revision; return that revision."""
        joints = [JointSettings(joint=j, **dict(zip(settings.NAMES, values[j * PER_JOINT:
                                                                            (j + 1) * PER_JOINT])))
                  for j in settings.JOINTS]
        msg = ArmSettings(revision=self.revision, joints=joints)
        msg.header.stamp = rospy.Time.now()
        self.publisher.publish(msg)
        self.revision += 1
        return msg.revision

    def stop(self):
        """Unregister, like a config_X that exits."""
        self.publisher.unregister()


class TempConfig:
    """config_L serving a fresh ini file in a new temp dir, seeded from seed_file.

    Nothing is left in ROS_HOME; stop() stops the node and removes the dir.
    """

    def __init__(self, launch, seed_file):
        self.dir = tempfile.mkdtemp(prefix='robopuppet_serial_test_')
        self.path = os.path.join(self.dir, 'arm_L.ini')
        self.process = launch.launch(Node(
            'robopuppet', 'config', name='config_L', namespace='/',
            args='_arm_side:=L _file_name:=%s _seed_file:=%s' % (self.path, seed_file)))
        # Serving and listening to opmode: an opmode published from now on reaches this node.
        rospy.wait_for_service('%s/%s' % (NS, interface.GET_CONFIG), timeout=30.0)
        wait_for(lambda: any(t == '%s/%s' % (NS, interface.OPMODE) and '/config_L' in nodes
                             for t, nodes in rosgraph.Master('/serial_test').getSystemState()[1]),
                 30.0, 'config_L subscribed to opmode')

    def stop(self):
        self.process.stop()
        shutil.rmtree(self.dir, ignore_errors=True)


def is_serial_link_status(status):
    """Return True for serial_L's link status: found by the rule of robopuppet.interface."""
    return status.hardware_id == NS and status.name.endswith(interface.DIAG_LINK)


class Watcher:
    """Keep the device's configs and opmodes, joint states, serial_L's diagnostics and
    warnings, and config_L's errors."""

    def __init__(self):
        self.lock = threading.Lock()
        self.device_config = None
        self.device_configs = []  # every one seen
        self.device_opmode = None
        self.device_opmodes = []  # every one seen
        self.joint_states = []
        self.diagnostics = {}  # the newest values, plus 'level' and 'message'
        self.diagnostics_times = []  # when each status arrived
        self.warnings = []
        self.config_errors = []  # config_L's errors
        self.own_logs = 0  # this test node's own log lines heard back on /rosout
        self._subs = [
            rospy.Subscriber(topic(interface.SIM_DEVICE_CONFIG, SIM), Float32MultiArray,
                             self._on_config),
            rospy.Subscriber(topic(interface.SIM_DEVICE_OPMODE, SIM), String, self._on_opmode),
            rospy.Subscriber(topic(interface.JOINT_STATES), JointState, self._on_states,
                             queue_size=1000),
            rospy.Subscriber(interface.DIAGNOSTICS, DiagnosticArray, self._on_diagnostics,
                             queue_size=100),
            rospy.Subscriber('/rosout', Log, self._on_log, queue_size=100)]

    def listen(self):
        """Return once /rosout lines reach this watcher (log until its own line comes back)."""
        def heard():
            rospy.loginfo('%s: listening to /rosout', rospy.get_name())
            return wait_for(lambda: self.own_logs, 0.5)
        assert wait_for(heard, 10.0), 'no /rosout line came back'

    def _on_config(self, msg):
        with self.lock:
            self.device_config = list(msg.data)
            self.device_configs.append(self.device_config)

    def _on_opmode(self, msg):
        with self.lock:
            self.device_opmode = msg.data
            self.device_opmodes.append(msg.data)

    def _on_states(self, msg):
        with self.lock:
            self.joint_states.append((time.monotonic(), msg))

    def _on_diagnostics(self, msg):
        for status in msg.status:
            if is_serial_link_status(status):
                with self.lock:
                    self.diagnostics = {kv.key: kv.value for kv in status.values}
                    self.diagnostics['level'] = status.level
                    self.diagnostics['message'] = status.message
                    self.diagnostics_times.append(time.monotonic())

    def _on_log(self, msg):
        with self.lock:
            if msg.name == '/serial_L' and msg.level >= Log.WARN:
                self.warnings.append(msg.msg)
            if msg.name == '/config_L' and msg.level >= Log.ERROR:
                self.config_errors.append(msg.msg)
            if msg.name == rospy.get_name():
                self.own_logs += 1

    def states_since(self, start_s):
        with self.lock:
            return [m for t, m in self.joint_states if t >= start_s]

    def latest_state(self):
        with self.lock:
            return self.joint_states[-1][1] if self.joint_states else None

    def diagnostics_since(self, start_s):
        """Return how many serial_L statuses arrived since start_s (monotonic)."""
        with self.lock:
            return sum(1 for t in self.diagnostics_times if t >= start_s)

    def warnings_with(self, text):
        with self.lock:
            return [w for w in self.warnings if text in w]
