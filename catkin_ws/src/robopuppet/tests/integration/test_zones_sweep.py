#!/usr/bin/python3
"""rostest: the keep-out zones hold for Baxter's measured pose during a fast random sweep.

main_sim with its defaults (config/zones.yaml, the stand-in's bed). Puppet R drives both Baxter
arms at once (button 3: the right arm as is; button 2: the left arm mirrored) while the
operator's hand goes through random poses across the puppet's whole range at its top speed for
SWEEP_S seconds (seed: $ZONES_SWEEP_SEED, default 1, printed). Every /robot/joint_states sample
of both arms, from the first press on, goes through the capsule model (sweep_harness); none may
be inside a zone, and Baxter must really have followed.
"""
import os
import unittest

import rospy
import rostest

from robopuppet import interface
from hand_pose import HAND_POSE
from sweep_harness import (ARM_SIDES, Recorder, inside_message, keep_following, package_guards,
                           report, start_following, sweeping_hand, travel)
from teleop_harness import PuppetArm

SEED = int(os.environ.get('ZONES_SWEEP_SEED', '1'))
SWEEP_S = 60.0
SAMPLE_RATE_HZ = 100.0     # the stand-in's /robot/joint_states
MIN_TRAVEL_RAD = 15.0      # each arm's measured path over the sweep, summed over its joints ...
MIN_SPAN_RAD, MIN_SPANS = 1.0, 4   # ... and at least MIN_SPANS joints over this range
MAX_LOST = 0.1             # share of the sweep arm_R may spend in faults (each resumed by a press)


class ZonesSweepTest(unittest.TestCase):

    def test_a_fast_random_sweep_keeps_baxter_out(self):
        guards, puppet, recorder = package_guards(), PuppetArm('R'), Recorder('R')
        start = start_following(puppet, recorder, interface.BAXTER_SIDES, HAND_POSE)
        print('sweep seed %d (ZONES_SWEEP_SEED), %.0f s' % (SEED, SWEEP_S))
        sweep_start = rospy.get_time()
        with sweeping_hand(puppet, SEED) as poses:
            faults = keep_following(puppet, ARM_SIDES['both'], SWEEP_S)
        end = rospy.get_time()
        found = report(guards, recorder, start, end, ('right', 'left'), sweep_start)
        lost_s = sum(resumed - fault for fault, resumed in faults)
        print('\n'.join(['sweep: %d poses, seed %d; arm_R faults: %d (%.1f s not following)'
                         % (len(poses), SEED, len(faults), lost_s)] + found.lines))
        # A zone entered is a failure whatever else happened; then that the sweep tested it.
        self.assertGreaterEqual(found.worst.clearance_m, 0.0,
                                inside_message(found.worst, 'the sweep (seed %d)' % SEED))
        self.assertEqual(found.missed, 0, '/robot/joint_states samples lost')
        # Every sample came (no gap in their sequence numbers) and the stand-in kept up: at
        # least half its rate even on a loaded machine.
        self.assertGreater(len(found.clearance['right']), 0.5 * SAMPLE_RATE_HZ * (end - start))
        self.assertLess(lost_s, MAX_LOST * SWEEP_S, 'Baxter did not follow for most of the '
                        'sweep: %d arm_R faults' % len(faults))
        for arm in interface.BAXTER_SIDES:
            path, spans = travel(found.moving[arm])
            self.assertGreater(path, MIN_TRAVEL_RAD, '%s arm barely moved' % arm)
            self.assertGreaterEqual((spans > MIN_SPAN_RAD).sum(), MIN_SPANS,
                                    '%s arm: joint ranges %s' % (arm, spans))


if __name__ == '__main__':
    rospy.init_node('test_zones_sweep')
    rostest.rosrun('robopuppet', 'zones_sweep', ZonesSweepTest)
