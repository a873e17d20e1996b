"""Statics of a Baxter arm: gravity torques, the tool point's Jacobian, its twist and wrench.

The link masses and centres of mass are facts of Rethink's baxter_description (baxter_common
1.2.0, urdf/baxter.urdf, the <inertial> of each arm link) and of its electric gripper
(rethink_ee_description, electric_gripper/rethink_electric_gripper.xacro: 0.3 kg at the gripper
base; the two fingers' 0.02 kg each are lumped there too). Our URDF has Rethink's link frames,
so the centres of mass carry over; it carries no <inertial> itself (docs/baxter_sim.md).

Conventions: base frame; a twist and a wrench are (linear, angular) 6-vectors of the tool point
(baxter_description.gripper_link, the point endpoint_state's pose is of); an effort is the
torque a joint applies (N m, about its axis). gravity(q) is what the joints apply to hold the
arm still; a wrench is the force (N) and torque (N m, about the tool point) the arm applies at
its tool point, the least-squares w with J^T w = the efforts beyond gravity.
Pure: numpy, no ROS, no clock.
"""
import collections
import math

import numpy as np

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_joint_command import TORQUE_MODE

GRAVITY_M_S2 = 9.80665
_IDENTITY = np.eye(4)
# Link (after its side's prefix): (mass kg, centre of mass xyz m in the link's frame).
LINK_INERTIALS = {
    'upper_shoulder': (5.70044, (0.01783, 0.00086, 0.19127)),
    'lower_shoulder': (3.22698, (0.06845, 0.00269, -0.00529)),
    'upper_elbow': (4.31272, (-0.00276, 0.00132, 0.18086)),
    'lower_elbow': (2.07206, (0.02611, 0.00159, -0.01117)),
    'upper_forearm': (2.24665, (-0.00168, 0.0046, 0.13952)),
    'lower_forearm': (1.60979, (0.06041, 0.00697, 0.006)),
    'wrist': (0.35093, (0.00198, 0.00125, 0.01855)),
    'hand': (0.19125, (0.01093, 0.00042, -0.01532)),
    'gripper_base': (0.3 + 2 * 0.02, (0.0, 0.0, 0.0)),
}

Endpoint = collections.namedtuple('Endpoint', 'gravity twist wrench')
Endpoint.__doc__ = """One arm's statics now: `gravity` (7,) N m, the joints' holding torques;
`twist` (6,) m/s and rad/s and `wrench` (6,) N and N m of the tool point in base."""


class ArmStatics:
    """Gravity torques, Jacobian, twist and wrench of one arm of a baxter_description.Description.

    Angles, velocities and efforts are (7,) sequences in order s0 .. w2. The chain is folded
    once into seven segments (the fixed transform to each joint, its axis, the mass that moves
    with it and that mass's centre), so a call costs seven 4x4 products.
    """

    def __init__(self, description, side):
        self.names = bd.arm_joint_names(side)
        self._fixed = []                       # per joint: fixed 4x4 from the previous joint
        self._axes = np.zeros((7, 3))
        self._rotations = []                   # per joint: (K, K @ K) of Rodrigues, 4x4
        self._masses = np.zeros(7)             # kg moving with joint k and no later joint
        moments = np.zeros((7, 3))             # their mass x centre, in joint k's moved frame
        fixed, index = np.eye(4), None
        for joint in description.chain(bd.gripper_link(side)):
            if joint.type != 'fixed':
                if joint.name not in self.names:
                    raise ValueError('joint %r between base and the tool point moves'
                                     % joint.name)
                index = self.names.index(joint.name)
                self._fixed.append(fixed @ joint.origin)
                self._axes[index] = joint.axis
                x, y, z = joint.axis
                k = np.zeros((4, 4))
                k[:3, :3] = [[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]]
                self._rotations.append((k, k @ k))
                fixed = np.eye(4)   # the child link's frame is the joint's, moved
            else:
                fixed = fixed @ joint.origin
            mass, com = LINK_INERTIALS.get(joint.child[len(side) + 1:], (0.0, None)) \
                if joint.child.startswith(side + '_') else (0.0, None)
            if mass:
                if index is None:
                    raise ValueError('link %r has mass but no arm joint moves it' % joint.child)
                self._masses[index] += mass
                moments[index] += mass * (fixed @ np.array(com + (1.0,)))[:3]
        if len(self._fixed) != 7:
            raise ValueError('the %s arm chain has %d joints, not 7' % (side, len(self._fixed)))
        self._tool = np.append(fixed[:3, 3], 1.0)   # in the last joint's moved frame
        self._centres = np.hstack([moments / np.maximum(self._masses, 1e-12)[:, None],
                                   np.ones((7, 1))])
        self.total_mass_kg = float(self._masses.sum())
        self._last = None   # (q, velocities, efforts) tuples and their Endpoint

    def frames(self, q):
        """Return (joint origins (7, 3), joint axes (7, 3), centres of the mass moving with
        each joint and no later one (7, 3), tool point (3,)) in base at angles q (rad)."""
        origins, axes, centres = np.empty((7, 3)), np.empty((7, 3)), np.empty((7, 3))
        pose = _IDENTITY
        for i, angle in enumerate(q):
            pose = pose @ self._fixed[i]
            origins[i] = pose[:3, 3]
            axes[i] = pose[:3, :3] @ self._axes[i]
            k, k2 = self._rotations[i]
            pose = pose @ (_IDENTITY + math.sin(angle) * k + (1.0 - math.cos(angle)) * k2)
            centres[i] = (pose @ self._centres[i])[:3]
        return origins, axes, centres, (pose @ self._tool)[:3]

    @staticmethod
    def _jacobian(origins, axes, tool):
        return np.vstack([np.cross(axes, tool - origins).T, axes.T])

    def jacobian(self, q):
        """Return the (6, 7) geometric Jacobian of the tool point in base at q (rad)."""
        origins, axes, _, tool = self.frames(q)
        return self._jacobian(origins, axes, tool)

    def _gravity(self, origins, axes, centres):
        # The weight of the mass beyond joint i (all of it: M_i at its centre C_i / M_i) turns
        # the joint by z_i . ((C_i - M_i p_i) x g); the joint holds with the opposite torque.
        beyond_mass = np.cumsum(self._masses[::-1])[::-1]
        beyond_moment = np.cumsum((self._masses[:, None] * centres)[::-1], axis=0)[::-1]
        gravity = np.array([0.0, 0.0, -GRAVITY_M_S2])
        arms = beyond_moment - beyond_mass[:, None] * origins
        return -np.einsum('ij,ij->i', axes, np.cross(arms, gravity))

    def gravity(self, q):
        """Return the (7,) torques (N m) the joints apply to hold the arm still at q (rad)."""
        origins, axes, centres, _ = self.frames(q)
        return self._gravity(origins, axes, centres)

    def endpoint(self, q, velocities, efforts):
        """Return the Endpoint at angles q (rad), joint velocities (rad/s) and the efforts
        beyond gravity (N m): the wrench is the least-squares w of J^T w = efforts. An arm
        holding still asks the same every cycle: the last answer is kept for it."""
        key = (tuple(q), tuple(velocities), tuple(efforts))
        if self._last is not None and self._last[0] == key:
            return self._last[1]
        origins, axes, centres, tool = self.frames(q)
        jacobian = self._jacobian(origins, axes, tool)
        efforts = np.asarray(efforts, np.float64)
        wrench = np.linalg.lstsq(jacobian.T, efforts, rcond=None)[0] if efforts.any() \
            else np.zeros(6)
        endpoint = Endpoint(self._gravity(origins, axes, centres),
                            jacobian @ np.asarray(velocities, np.float64), wrench)
        self._last = (key, endpoint)
        return endpoint


def arm_endpoint(statics, arm):
    """Return the Endpoint of a baxter_model.Arm now (its efforts are those beyond gravity)."""
    names = statics.names
    return statics.endpoint([arm.positions[n] for n in names],
                            [arm.velocities[n] for n in names], [arm.efforts[n] for n in names])


def holds_against_gravity(arm, enabled):
    """Return whether an arm's joints carry its weight: enabled and not commanded in torque
    mode (there the commanded torques act on top of the robot's own gravity compensation)."""
    return enabled and not (arm.mode == TORQUE_MODE and arm.last_command_s is not None)


def with_gravity(joints, arms, endpoints, enabled):
    """Return a joint_state tuple (names, positions, velocities, efforts) whose efforts add
    each holding arm's gravity torques (see holds_against_gravity)."""
    names, positions, velocities, efforts = joints
    extra = {}
    for side, arm in arms.items():
        if holds_against_gravity(arm, enabled):
            extra.update(zip(bd.arm_joint_names(side), endpoints[side].gravity.tolist()))
    return names, positions, velocities, [e + extra.get(n, 0.0) for n, e in zip(names, efforts)]
