#!/usr/bin/python3
"""rostest (config_respawn.test): a calibration is ONE request, and a killed config_R comes back.

config_R runs from arm.launch. The test applies and undoes a calibration of all seven joints
(home_angle and sign_angle, set_arm_config) over and over while it reads the ini file all the
time: every read holds the seven joints all old or all new, and each apply is one revision of
stored_settings. SIGKILL of config_R in the middle of that leaves the file all old or all new;
config_R respawns, serves get_config and publishes the file's settings again; it hears the
(stand-in) arm_X's teleop_state before it serves, so it refuses the calibration's Undo while
Baxter follows, and stores it once following stops.
"""
import os
import shutil
import signal
import threading
import unittest
import xmlrpc.client

import rosgraph
import rosnode
import rospy
import rostest

from config_testing import SERVICE, StoredSettings, joint_values
from waiting import wait_for
from robopuppet import interface, settings
from robopuppet.config import config_store
from robopuppet_msgs.msg import JointChange, TeleopState
from robopuppet_msgs.srv import GetConfig, SetArmConfig

NS = interface.puppet_ns('R')
NODE = '/config_R'
CALIBRATED = ('home_angle', 'sign_angle')


def set_arm_config(values, timeout_s=10.0):
    """Call config_R's set_arm_config with {joint: {name: value}}; return the response."""
    service = '%s/%s' % (NS, interface.SET_ARM_CONFIG)
    rospy.wait_for_service(service, timeout=timeout_s)
    return rospy.ServiceProxy(service, SetArmConfig)(
        [JointChange(joint, list(v), list(v.values())) for joint, v in sorted(values.items())])


def node_pid():
    """Return config_R's process id, or None while it is not there."""
    try:
        uri = rosnode.get_api_uri(rosgraph.Master('/config_respawn_test'), NODE, skip_cache=True)
        code, _, pid = xmlrpc.client.ServerProxy(uri).getPid('/config_respawn_test')
    except (OSError, TypeError, rosgraph.MasterException):
        return None
    return pid if code == 1 else None


def answers_get_config():
    """Return config_R's joint 0 {name: value} from get_config, or None when it does not answer."""
    try:
        return joint_values(rospy.ServiceProxy(SERVICE, GetConfig)(0))
    except (rospy.ServiceException, OSError):
        return None


class FileWatch(threading.Thread):
    """Read the ini file over and over; keep the calibrations seen (a name, or 'mixed: ...')."""

    def __init__(self, path, known):
        super().__init__(daemon=True)
        self.path, self.known, self.seen, self.reads = path, known, set(), 0
        self.stop = threading.Event()

    def state(self):
        with open(self.path) as ini:
            config, problems = config_store.parse(ini.read())
        assert problems == [], problems
        values = {j: {n: config[j][n] for n in CALIBRATED} for j in settings.JOINTS}
        return next((name for name, known in self.known.items() if values == known),
                    'mixed: %s' % values)

    def run(self):
        while not self.stop.is_set():
            self.seen.add(self.state())
            self.reads += 1


class ConfigRespawnTest(unittest.TestCase):

    def test_a_calibration_is_one_request_and_config_survives_a_kill(self):
        path = rospy.get_param('~ini_path')
        self.addCleanup(shutil.rmtree, os.path.dirname(path), True)
        stored = StoredSettings()
        self.addCleanup(stored.unregister)
        self.assertIsNotNone(stored.wait(0, 30), 'config_R publishing its settings')
        with open(path) as ini:
            config, _ = config_store.parse(ini.read())
        old = {j: {n: config[j][n] for n in CALIBRATED} for j in settings.JOINTS}
        new = {j: {'home_angle': config_store.to_float32(v['home_angle'] + 0.25),
                   'sign_angle': -v['sign_angle']} for j, v in old.items()}
        calibrations = {'old': old, 'new': new}
        watch = FileWatch(path, calibrations)
        self.assertEqual(watch.state(), 'old')

        answer = set_arm_config(new)
        self.assertTrue(answer.stored, answer.error)
        self.assertEqual([{n: getattr(j, n) for n in CALIBRATED} for j in answer.settings.joints],
                         [new[j] for j in settings.JOINTS])
        message = stored.wait(1)
        self.assertEqual([{n: getattr(j, n) for n in CALIBRATED} for j in message.joints],
                         [new[j] for j in settings.JOINTS], 'one revision holds all seven')
        self.assertEqual(watch.state(), 'new')

        # Apply and undo without a pause, reading the file all the while; kill config_R amid.
        churn_stop = threading.Event()

        def churn():
            for k in range(10 ** 6):
                if churn_stop.is_set():
                    return
                try:
                    set_arm_config((old, new)[k % 2], timeout_s=0.5)
                except (rospy.ServiceException, rospy.ROSException, OSError):
                    pass
        churner = threading.Thread(target=churn, daemon=True)
        watch.start()
        churner.start()
        self.addCleanup(watch.stop.set)
        self.assertTrue(wait_for(lambda: stored.messages()[-1].revision >= 9, 20),
                        'config_R storing calibrations')
        pid = node_pid()
        self.assertIsNotNone(pid)
        os.kill(pid, signal.SIGKILL)
        churn_stop.set()
        # The stand-in arm_X: Baxter's right arm follows this puppet (latched, as arm_X's, and
        # repeated, as arm_X repeats it), before config_R comes back.
        teleop = rospy.Publisher('%s/%s' % (NS, interface.TELEOP_STATE), TeleopState,
                                 queue_size=1, latch=True)
        following = [True]

        def tell(_event=None):
            teleop.publish(TeleopState(state=interface.FOLLOWING if following[0]
                                       else interface.READY, follow_right=following[0]))
        tell()
        timer = rospy.Timer(rospy.Duration(0.3), tell)
        self.addCleanup(timer.shutdown)
        churner.join(10)
        self.assertFalse(churner.is_alive())

        self.assertTrue(wait_for(lambda: node_pid() not in (None, pid)
                                 and answers_get_config(), 20), 'config_R respawned')
        watch.stop.set()
        watch.join(10)
        after = watch.state()
        rospy.loginfo('file states seen in %d reads: %s; after the kill: %s', watch.reads,
                      sorted(watch.seen), after)
        self.assertEqual(watch.seen, {'old', 'new'}, 'never a mix of old and new joints')
        self.assertIn(after, ('old', 'new'))
        again = wait_for(lambda: [m for m in stored.messages() if m.revision == 0][1:], 10)
        self.assertTrue(again, 'the respawned config_R publishes its settings')
        self.assertEqual([{n: getattr(j, n) for n in CALIBRATED} for j in again[-1].joints],
                         [calibrations[after][j] for j in settings.JOINTS])

        # Undo of what the file holds: refused at once while Baxter follows, then stored.
        undo = calibrations['old' if after == 'new' else 'new']
        answer = set_arm_config(undo)
        self.assertFalse(answer.stored)
        self.assertIn('press 3', answer.error)
        self.assertEqual(FileWatch(path, calibrations).state(), after, 'nothing written')
        following[0] = False
        tell()
        self.assertTrue(wait_for(lambda: set_arm_config(undo).stored, 10),
                        'Undo once following stopped')
        self.assertEqual(FileWatch(path, calibrations).state(),
                         'old' if after == 'new' else 'new')
        self.assertTrue(wait_for(lambda: [m for m in stored.messages()
                                          if m.revision == 1][1:], 10),
                        'the respawned config_R published the undone revision 1')


if __name__ == '__main__':
    rospy.init_node('config_respawn_test')
    rostest.rosrun('robopuppet', 'config_respawn', ConfigRespawnTest)
