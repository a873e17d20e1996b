"""Cartesian velocity to joint angles: one damped-least-squares step per device step; and IK
that settles for a near answer where the exact solver stalls (pure)."""
import numpy as np

from robopuppet import baxter_description
from robopuppet.baxter_sim.baxter_ik import ArmIK, quaternion_matrix, rotation_error

DAMPING = 0.02   # lambda of the damped least squares (m, rad): slows the arm near singularities
ITERATIONS = 3   # Jacobian steps per device step
LOOSE_M, LOOSE_RAD, LOOSE_ITERATIONS = 0.004, 0.05, 100   # solve_near's good-enough answer
LOOSE_DAMPING, LOOSE_STEP_RAD = 0.05, 0.3
NEAR_SEEDS = 6   # solve_near tries this many of the IK's null-space map seeds


def axis_angle_matrix(rotation_vector):
    """Return the 3x3 rotation of a rotation vector (axis times angle, rad)."""
    angle = float(np.linalg.norm(rotation_vector))
    if angle < 1e-12:
        return np.eye(3)
    return baxter_description.axis_angle_matrix(np.asarray(rotation_vector) / angle, angle)


class CartesianArm:
    """One Baxter arm's kinematics for the study's devices.

    Args:
        side: 'left' or 'right'.
        description: a baxter_description.Description (the package's URDF when None).
        bounds: (lower, upper) 7 angles (rad) narrower than the joint limits, e.g. what a
            puppet can show; clip and solve_near keep within them.
    """

    def __init__(self, side, description=None, bounds=None):
        self._ik = ArmIK(description or baxter_description.load(), side)
        self.lower, self.upper = bounds or (self._ik.lower, self._ik.upper)

    def clip(self, q):
        """Return q (7 rad) clipped into the joint limits."""
        return np.clip(np.asarray(q, dtype=float), self.lower, self.upper)

    def tip(self, q):
        """Return the gripper's tool point (xyz m, 3x3 rotation) in base at q."""
        pose = self._ik.forward(np.asarray(q, dtype=float))[0]
        return pose[:3, 3].copy(), pose[:3, :3].copy()

    def step(self, q, twist, dt_s):
        """Return q moved by twist (vx, vy, vz m/s, wx, wy, wz rad/s in base) for dt_s, within
        the joint limits (a joint at its limit stays there; near a singularity the damping
        shortens the step)."""
        q = self.clip(q)
        twist = np.asarray(twist, dtype=float)
        if not np.any(twist):
            return q
        start, rotation = self.tip(q)
        goal = start + twist[:3] * dt_s
        goal_rotation = axis_angle_matrix(twist[3:] * dt_s) @ rotation
        for _ in range(ITERATIONS):   # re-linearised: the step lands where asked
            pose, jacobian = self._ik.forward(q)
            error = np.concatenate([goal - pose[:3, 3],
                                    rotation_error(goal_rotation, pose[:3, :3])])
            q = self.clip(q + jacobian.T @ np.linalg.solve(
                jacobian @ jacobian.T + DAMPING ** 2 * np.eye(6), error))
        return q

    def solve(self, xyz, quaternion, seed):
        """Return 7 angles (rad, within limits) putting the tool point at the pose (m; x, y,
        z, w), seeded with seed, or None when it cannot be reached (or is not finite)."""
        if not (np.all(np.isfinite(xyz)) and np.all(np.isfinite(quaternion))):
            return None
        try:
            rotation = quaternion_matrix(quaternion)
        except ValueError:
            return None
        return self._ik.solve(xyz, rotation, seed)

    @property
    def seeds(self):
        """The IK's null-space map seeds (7 rad each): other arm configurations to start from."""
        return self._ik.ns_map_seeds

    def solve_near(self, xyz, rotation, seed):
        """Return 7 angles within bounds putting the tool point at xyz (m) and rotation (3x3):
        exactly, else within LOOSE_M and LOOSE_RAD (near a singularity the exact solver
        stalls), from seed, then from NEAR_SEEDS of the map's seeds; None when none reaches
        it."""
        q = self._within(self._ik.solve(xyz, rotation, seed))
        for start in [] if q is not None else [seed] + list(self.seeds[:NEAR_SEEDS]):
            q = None if start is seed else self._within(self._ik.solve(xyz, rotation, start))
            q = q if q is not None else self._loose(xyz, rotation, start)
            if q is not None:
                break
        return q

    def _within(self, q):
        return None if q is None or np.any(q < self.lower) or np.any(q > self.upper) else q

    def _loose(self, xyz, rotation, seed):
        q = self.clip(seed)
        for _ in range(LOOSE_ITERATIONS):
            pose, jacobian = self._ik.forward(q)
            error = np.concatenate([xyz - pose[:3, 3], rotation_error(rotation, pose[:3, :3])])
            if np.linalg.norm(error[:3]) < LOOSE_M and np.linalg.norm(error[3:]) < LOOSE_RAD:
                return q
            step = jacobian.T @ np.linalg.solve(
                jacobian @ jacobian.T + LOOSE_DAMPING ** 2 * np.eye(6), error)
            q = self.clip(q + step * min(1.0, LOOSE_STEP_RAD / max(np.linalg.norm(step), 1e-9)))
        return None
