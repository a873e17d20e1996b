"""Inverse kinematics of Baxter's arms: what /ExternalTools/<side>/PositionKinematicsNode serves.

Pure: numpy only. Seeded damped least squares on the URDF's chain from `base` to the side's
`<side>_gripper` tool point (the endpoint_state frame), within the joint limits. A pose counts as
reached within POSITION_TOLERANCE_M and ORIENTATION_TOLERANCE_RAD; otherwise the next seed is
tried, and when none reaches it the pose is reported unreachable.
"""
import collections
import math

import numpy as np

from robopuppet import baxter_description as bd

POSITION_TOLERANCE_M = 1e-4
ORIENTATION_TOLERANCE_RAD = 1e-3
MAX_ITERATIONS = 150
DAMPING = 0.02            # lambda of the damped least squares (m, rad)
MAX_STEP_RAD = 0.3        # a step of the joints is scaled down to at most this norm
STALL_ITERATIONS = 20     # a seed is given up when its error did not shrink 1 % in this many
RANDOM_SEEDS = 40         # seeds spread over the joint ranges, after NS_MAP_SEEDS (fixed: 0)
# SolvePositionIK's seed modes; result_type reports the one that found the solution.
SEED_AUTO, SEED_USER, SEED_CURRENT, SEED_NS_MAP = 0, 1, 2, 3
RESULT_INVALID = 0
# The stand-in's stand-in for Rethink's null-space map: these poses (s0 s1 e0 e1 w0 w1 w2), then
# RANDOM_SEEDS more spread uniformly over the joint ranges (the same every start).
NS_MAP_SEEDS = ((0.0, -0.55, 0.0, 0.75, 0.0, 1.26, 0.0),
                (0.0, 0.0, 0.0, 1.5, 0.0, 0.0, 0.0),
                (0.5, -0.8, -1.0, 1.8, 0.5, 0.8, 0.0),
                (-0.5, -0.8, 1.0, 1.8, -0.5, 0.8, 0.0),
                (0.0, -1.0, 0.0, 2.2, 0.0, -0.8, 0.0),
                (0.8, 0.3, 0.0, 0.3, 0.0, 1.0, 0.0))

Solution = collections.namedtuple('Solution', 'names positions result_type')
Solution.__doc__ = """One pose's answer: `names` the 7 arm joints, `positions` rad (None when no
seed reached the pose), `result_type` the seed mode that found it (RESULT_INVALID: none)."""


def quaternion_matrix(quaternion):
    """Return the 3x3 rotation of a quaternion (x, y, z, w), normalised.

    Raises:
        ValueError: the quaternion is zero or not finite.
    """
    q = np.asarray(quaternion, dtype=float)
    norm = np.linalg.norm(q)
    if not (np.all(np.isfinite(q)) and norm > 1e-9):
        raise ValueError('orientation is not a usable quaternion: %s' % (tuple(quaternion),))
    x, y, z, w = q / norm
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def rotation_error(target, actual):
    """Return the rotation vector (rad) that turns `actual` into `target` (3x3, base frame)."""
    r = target @ actual.T
    v = 0.5 * np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    sin = np.linalg.norm(v)
    angle = math.atan2(sin, (np.trace(r) - 1.0) / 2.0)
    if sin < 1e-9:
        if angle < 1.0:
            return v
        # Half a turn: the axis is the column of r + I with the largest norm.
        columns = r + np.eye(3)
        axis = columns[:, np.argmax(np.linalg.norm(columns, axis=0))]
        return axis / np.linalg.norm(axis) * angle
    return v / sin * angle


class ArmIK:
    """Damped least squares IK of one arm.

    Args:
        description: a baxter_description.Description.
        side: 'left' or 'right'.
    """

    def __init__(self, description, side):
        self.names = bd.arm_joint_names(side)
        self.chain = description.chain(bd.gripper_link(side))
        limits = description.arm_limits(side)
        self.lower = np.array([lim.lower for lim in limits])
        self.upper = np.array([lim.upper for lim in limits])
        spread = np.random.default_rng(0).uniform(self.lower, self.upper,
                                                  (RANDOM_SEEDS, len(limits)))
        # Beyond this distance (m) from the first joint no angles reach: the sum of the links.
        first = self.chain.index(next(j for j in self.chain if j.name == self.names[0]))
        self.shoulder = description.transform({}, self.chain[first].parent)[:3, 3] \
            + self.chain[first].origin[:3, 3]
        self.reach_m = sum(np.linalg.norm(j.origin[:3, 3]) for j in self.chain[first + 1:])
        self.ns_map_seeds = [np.array(seed) for seed in NS_MAP_SEEDS] + list(spread)

    def forward(self, q):
        """Return (4x4 tool pose in base, 6x7 geometric Jacobian) at joint angles q (rad)."""
        index = {name: i for i, name in enumerate(self.names)}
        pose = np.eye(4)
        axes, origins = [], []
        for joint in self.chain:
            pose = pose @ joint.origin
            if joint.name in index:
                axes.append(pose[:3, :3] @ joint.axis)
                origins.append(pose[:3, 3].copy())
                motion = np.eye(4)
                motion[:3, :3] = bd.axis_angle_matrix(joint.axis, q[index[joint.name]])
                pose = pose @ motion
        tip = pose[:3, 3]
        jacobian = np.zeros((6, len(self.names)))
        for i, (axis, origin) in enumerate(zip(axes, origins)):
            jacobian[:3, i] = np.cross(axis, tip - origin)
            jacobian[3:, i] = axis
        return pose, jacobian

    def solve(self, xyz, rotation, seed):
        """Return joint angles (rad, within limits) reaching the pose from seed, or None.

        Args:
            xyz: target position of the tool point in base (m).
            rotation: its 3x3 orientation in base.
            seed: 7 start angles (rad), clamped into the limits.
        """
        q = np.clip(np.asarray(seed, dtype=float), self.lower, self.upper)
        target = np.asarray(xyz, dtype=float)
        best, best_at = math.inf, 0
        for iteration in range(MAX_ITERATIONS):
            pose, jacobian = self.forward(q)
            error = np.concatenate([target - pose[:3, 3], rotation_error(rotation, pose[:3, :3])])
            if (np.linalg.norm(error[:3]) < POSITION_TOLERANCE_M
                    and np.linalg.norm(error[3:]) < ORIENTATION_TOLERANCE_RAD):
                return q
            size = np.linalg.norm(error)
            if size < 0.99 * best:
                best, best_at = size, iteration
            elif iteration - best_at > STALL_ITERATIONS:
                return None
            step = jacobian.T @ np.linalg.solve(jacobian @ jacobian.T + DAMPING ** 2 * np.eye(6),
                                                error)
            norm = np.linalg.norm(step)
            if norm > MAX_STEP_RAD:
                step *= MAX_STEP_RAD / norm
            q = np.clip(q + step, self.lower, self.upper)
        return None

    def invalid(self):
        """Return the Solution of a pose that no seed reaches."""
        return Solution(self.names, None, RESULT_INVALID)

    def solve_seeded(self, xyz, quaternion, user_seed, current, seed_mode):
        """Return a Solution for one pose, trying seeds like Rethink's IK service.

        Args:
            xyz, quaternion: the target pose in base (m; x, y, z, w).
            user_seed: {joint name: rad} from the request (may be empty or partial: the
                missing joints come from current).
            current: {joint name: rad} of the arm now.
            seed_mode: SEED_AUTO tries the user seed (if any), the current angles, then the
                null-space map seeds; another mode tries only that kind.
        Raises:
            ValueError: the pose is not finite or the quaternion is unusable.
        """
        if not np.all(np.isfinite(np.asarray(xyz, dtype=float))):
            raise ValueError('position is not finite: %s' % (tuple(xyz),))
        rotation = quaternion_matrix(quaternion)
        if np.linalg.norm(np.asarray(xyz, dtype=float) - self.shoulder) > self.reach_m:
            return self.invalid()
        now = [current[n] for n in self.names]
        seeds = []
        if user_seed and seed_mode in (SEED_AUTO, SEED_USER):
            seeds.append((SEED_USER, [user_seed.get(n, c) for n, c in zip(self.names, now)]))
        if seed_mode in (SEED_AUTO, SEED_CURRENT):
            seeds.append((SEED_CURRENT, now))
        if seed_mode in (SEED_AUTO, SEED_NS_MAP):
            seeds.extend((SEED_NS_MAP, seed) for seed in self.ns_map_seeds)
        for kind, seed in seeds:
            q = self.solve(xyz, rotation, seed)
            if q is not None:
                return Solution(self.names, [float(v) for v in q], kind)
        return self.invalid()

