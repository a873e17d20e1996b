"""Shared helpers of the serial integration tests (serial_sim_test.py, serial_recovery_test.py)."""
import os
import shutil
import tempfile
import threading
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from roslaunch.core import Node
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, String

from robopuppet import settings
from robopuppet.config import config_store

SIM = '/puppet_sim/arm_L'
NS = '/puppet/arm_L'


def seed_values(path):
    """Return the 84 settings of an ini file, joint-major in settings.NAMES order."""
    with open(path) as ini:
        config, problems = config_store.parse(ini.read())
    assert not problems, problems
    return [config[j][n] for j in settings.JOINTS for n in settings.NAMES]


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

    def stop(self):
        self.process.stop()
        shutil.rmtree(self.dir, ignore_errors=True)


def wait_for(predicate, timeout_s, step_s=0.02):
    """Poll predicate until it is true; return the seconds it took, or None on timeout."""
    start = time.monotonic()
    while time.monotonic() - start < timeout_s and not rospy.is_shutdown():
        if predicate():
            return time.monotonic() - start
        time.sleep(step_s)
    return None


class Watcher:
    """Keep the device's configs and opmodes, joint states, diagnostics, serial_L's warnings
    and config_L's errors."""

    def __init__(self):
        self.lock = threading.Lock()
        self.device_config = None
        self.device_configs = []  # every one seen
        self.device_opmode = None
        self.device_opmodes = []  # every one seen
        self.joint_states = []
        self.diagnostics = {}  # the values, plus 'level' and 'message'
        self.warnings = []
        self.config_errors = []  # config_L's errors
        self._subs = [
            rospy.Subscriber(SIM + '/device_config', Float32MultiArray, self._on_config),
            rospy.Subscriber(SIM + '/device_opmode', String, self._on_opmode),
            rospy.Subscriber(NS + '/joint_states', JointState, self._on_states, queue_size=1000),
            rospy.Subscriber('/diagnostics', DiagnosticArray, self._on_diagnostics),
            rospy.Subscriber('/rosout', Log, self._on_log, queue_size=100)]

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
            if status.name.startswith('/serial_L'):
                with self.lock:
                    self.diagnostics = {kv.key: kv.value for kv in status.values}
                    self.diagnostics['level'] = status.level
                    self.diagnostics['message'] = status.message

    def _on_log(self, msg):
        if msg.name == '/serial_L' and msg.level >= Log.WARN:
            with self.lock:
                self.warnings.append(msg.msg)
        if msg.name == '/config_L' and msg.level >= Log.ERROR:
            with self.lock:
                self.config_errors.append(msg.msg)

    def states_since(self, start_s):
        with self.lock:
            return [m for t, m in self.joint_states if t >= start_s]

    def latest_state(self):
        with self.lock:
            return self.joint_states[-1][1] if self.joint_states else None
