#!/usr/bin/python3
"""rostest: the keep-out zones hold for Baxter's measured pose during a replay past the patient.

main_sim with its defaults (config/zones.yaml, the stand-in's bed). A synthetic episode whose
recorded commands pass 3.6 cm above the patient-body zone at near the arm's full speed, each
command clear of every zone (ZoneGuard.limit from the one before: what the replay checks), is
replayed onto the stand-in with `rosrun robopuppet replay`. The stand-in (mode 1, speed ratio
0.3) lags and cuts the corner; every /robot/joint_states sample of both arms from the start of
the replay until Baxter is still goes through the capsule model (sweep_harness): none may be
inside a zone. The replay may finish or stop at a zone, never enter one.
"""
import math
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np
import rosbag
import rospy
import rostest
import yaml
from baxter_core_msgs.msg import JointCommand

from robopuppet import baxter_description as bd, interface
from hand_pose import HAND_POSE
from sweep_harness import Recorder, inside_message, package_guards, report, travel
from teleop_harness import PuppetArm
from waiting import wait_for

# The right arm from A across the patient to B, then down to C, at EPISODE_SPEED x the velocity
# limits. Baxter, at 0.3 x them in mode 1, lowers its elbow before its shoulder has swung across:
# a model of the stand-in puts the gripper 7.7 cm into the patient-body zone.
EPISODE = ([0.383, -0.72, 0.038, 0.992, -0.075, 1.461, 0.0],
           [1.652, -0.67, -0.114, 1.114, 0.452, 1.262, 0.0],
           [1.652, -0.449, -0.319, 1.452, 0.452, 1.286, 0.0])
EPISODE_SPEED, RATE_HZ = 0.8, 100.0
DWELL_S = (0.5, 2.0)   # at A, and at C (Baxter catching up while commands still come)
MIN_CLEARANCE_M = 0.035   # every recorded command this far from every zone
NEAR_M = 0.06             # ... and Baxter measured nearer than this to one: it passed near


def episode_path():
    """Return the episode's (n, 7) right-arm commands at RATE_HZ."""
    speeds = EPISODE_SPEED * np.array([lim.velocity for lim in bd.arm_limits('right')])
    rows = [np.tile(EPISODE[0], (int(DWELL_S[0] * RATE_HZ), 1))]
    for a, b in zip(EPISODE, EPISODE[1:]):
        a, b = np.array(a), np.array(b)
        steps = math.ceil(float((np.abs(b - a) / speeds).max()) * RATE_HZ)
        rows.append(a + np.outer(np.arange(1, steps + 1) / steps, b - a))
    rows.append(np.tile(EPISODE[-1], (int(DWELL_S[1] * RATE_HZ), 1)))
    return np.concatenate(rows)


def write_episode(directory, path):
    """Write path as an episode's right-arm commands (bag and yaml); return the bag's path."""
    bag_path, t0 = os.path.join(directory, 'near_patient.bag'), rospy.Time(1000)
    names = bd.arm_joint_names('right')
    with rosbag.Bag(bag_path, 'w') as bag:
        for k, angles in enumerate(path):
            bag.write(interface.limb_topic('right', 'joint_command'), JointCommand(
                mode=JointCommand.POSITION_MODE, names=names, command=list(angles)),
                t0 + rospy.Duration(k / RATE_HZ))
    with open(os.path.join(directory, 'near_patient.yaml'), 'w') as stream:
        yaml.safe_dump({'format_version': 1, 'sides': ['R'], 'sim': True}, stream)
    return bag_path


class ZonesReplayTest(unittest.TestCase):

    def test_a_replay_past_the_patient_keeps_baxter_out(self):
        guards, puppet, recorder = package_guards(), PuppetArm('R'), Recorder('R')
        path = episode_path()
        guard = guards['right']
        self.assertGreater(min(guard.clearance(q).min() for q in path), MIN_CLEARANCE_M)
        self.assertEqual([k for k in range(1, len(path))
                          if guard.limit(path[k - 1], path[k])[1] is not None], [])
        wait_for(lambda: puppet.angles is not None and recorder.baxter, 60,
                 'the puppet and Baxter')
        start = puppet.angles
        puppet.hand(HAND_POSE)   # the operator's hand holds the puppet still
        puppet.wait_still(start)
        directory = tempfile.mkdtemp(prefix='zones_sweep_replay_')
        self.addCleanup(shutil.rmtree, directory, True)
        bag = write_episode(directory, path)
        started = rospy.get_time()
        process = subprocess.Popen(['rosrun', 'robopuppet', 'replay', bag],
                                   stderr=subprocess.PIPE, text=True)
        _, err = process.communicate(timeout=90)
        wait_for(recorder.still, 20, 'Baxter still after the replay')
        print('replay exit %d:\n%s' % (process.returncode, err))
        found = report(guards, recorder, started, rospy.get_time(), ('right', 'left'),
                       lag=False)
        print('\n'.join(['replay past the patient:'] + found.lines))
        # A zone entered is a failure whatever else happened; then that the replay tested it.
        self.assertGreaterEqual(found.worst.clearance_m, 0.0,
                                inside_message(found.worst, 'the replay'))
        self.assertIn(process.returncode, (0, 1), err)
        if process.returncode == 1:
            self.assertIn('keep-out zone', err)
        self.assertGreater(travel(found.measured['right'])[0], 2.0, 'the replay hardly moved '
                           'Baxter')
        self.assertLess(found.clearance['right'].min(), NEAR_M, 'Baxter never came near a zone')


if __name__ == '__main__':
    rospy.init_node('test_zones_sweep_replay')
    rostest.rosrun('robopuppet', 'zones_sweep_replay', ZonesReplayTest)
