"""The tests' hand pose (tests/integration/hand_pose.py) keeps both Baxter arms out of the
package's keep-out zones, which main_sim enforces by default: a test driving Baxter there is not
held back by a zone (a change of config/zones.yaml that breaks those tests fails here first)."""
import itertools
import os
import sys

import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.arm.joint_motion import mirror
from robopuppet.world import arm_capsules, zones

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'integration'))
from hand_pose import HAND_POSE  # noqa: E402

ZONES_FILE = bd.URDF_PATH.replace('urdf/baxter.urdf', 'config/zones.yaml')
NEUTRAL = np.array([bd.NEUTRAL_POSE[s] for s in bd.ARM_JOINT_SUFFIXES])
SWINGS_RAD = {0: 0.3, 3: 0.5}   # the tests' hand swings around the pose, per joint
PATH_MARGIN_M = 0.05            # on the way from neutral
POSE_MARGIN_M = 0.15            # at and around the pose
STEP_S = 0.01                   # arm_X's command period


def approach(target, speeds_rad_s):
    """Return the commands of arm_X's speed budget from neutral to target (each joint at most
    its speed x STEP_S a command; 0.5 rad/s while approaching, the URDF's limits when tracking),
    and the straight joint-space line between them."""
    path, q = [], NEUTRAL.copy()
    while np.abs(target - q).max() > 1e-9:
        q = q + np.clip(target - q, -speeds_rad_s * STEP_S, speeds_rad_s * STEP_S)
        path.append(q)
    return path + [NEUTRAL + s * (target - NEUTRAL) for s in np.linspace(0.0, 1.0, 101)]


@pytest.mark.parametrize('side', ['right', 'left'])
def test_the_hand_pose_keeps_the_arm_out_of_the_zones(side):
    with open(bd.URDF_PATH) as stream:
        capsules = arm_capsules.ArmCapsules(bd.load(), stream.read(), side)
    guard = zones.ZoneGuard(capsules, zones.load_zones(ZONES_FILE))
    pose = np.array(HAND_POSE if side == 'right' else mirror(HAND_POSE))
    limits = bd.arm_limits(side)
    velocity = np.array([lim.velocity for lim in limits])

    def least(configurations):
        return min(guard.clearance(q).min() for q in configurations)

    assert least(approach(pose, np.full(7, 0.5)) + approach(pose, velocity)) >= PATH_MARGIN_M
    around = []
    for offsets in itertools.product(*(np.linspace(-a, a, 7) for a in SWINGS_RAD.values())):
        q = pose.copy()
        q[list(SWINGS_RAD)] += offsets
        assert all(lim.lower + 0.3 <= a <= lim.upper - 0.3 for a, lim in zip(q, limits))
        around.append(q)
    assert least(around) >= POSE_MARGIN_M
