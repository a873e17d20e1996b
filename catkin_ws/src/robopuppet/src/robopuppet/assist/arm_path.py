"""Joint paths of one Baxter arm through tool-point positions, for the scripted demonstrator.

Each position is solved by damped least squares on the stand-in's kinematics (baxter_sim's
ArmIK: forward kinematics and Jacobian), seeded with the previous solution so that the joints
move smoothly: weighted least squares of the position (exact), the orientation (gripper pointing
down, as far as the joints allow) and the distance from a rest posture (which settles the arm's
redundant freedom, so that the angles are a smooth function of the path). The joints
stay inside Baxter's URDF limits and the puppet's default angle range (settings.py's
angle_min/angle_max: a puppet reports no angle beyond it, so the operator could not show one),
each with a margin. Pure: numpy only.
"""
import numpy as np

from robopuppet import baxter_description as bd, settings
from robopuppet.baxter_sim.baxter_ik import NS_MAP_SEEDS, rotation_error
from robopuppet.assist.tasks import arm_kinematics

LIMIT_MARGIN_RAD = 0.08
ORIENTATION_WEIGHT_M = 0.02  # m per rad: how much a rad of orientation error counts
REST_WEIGHT_M = 0.005        # m per rad: how much a rad from the rest posture counts
DAMPING = 0.002
CONVERGED_RAD = 1e-5         # a solve stops when its step is this small
MAX_STEP_RAD = 0.2
REACHED_M = 1e-3             # a position counts as reached this near
KEY_STRIDE = 5               # solve() solves every fifth position, and the last
FIRST_ITERATIONS, NEXT_ITERATIONS = 400, 40
# Gripper pointing down (tool z along -z of base), tool x backwards.
DOWN = np.array([[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]])
# The rest posture of the right arm (s0 s1 e0 e1 w0 w1 w2, rad); the left's is mirrored.
REST_RIGHT = np.array([0.6, -0.7, 0.0, 1.2, 0.0, 0.9, 0.0])
MIRROR = np.array([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0])


class PathError(ValueError):
    """A position of a plan is out of the arm's reach within its limits."""


def joint_bounds(side):
    """Return (lower, upper) (7,) angles (rad) the demonstrator keeps a side's joints within."""
    limits = bd.arm_limits(side)
    puppet_low = settings.DEFAULTS['angle_min'] + LIMIT_MARGIN_RAD
    puppet_high = settings.DEFAULTS['angle_max'] - LIMIT_MARGIN_RAD
    lower = np.array([max(lim.lower + LIMIT_MARGIN_RAD, puppet_low) for lim in limits])
    upper = np.array([min(lim.upper - LIMIT_MARGIN_RAD, puppet_high) for lim in limits])
    return lower, upper


def rest_posture(side):
    """Return the rest posture (7 rad) of a side."""
    return REST_RIGHT.copy() if side == 'right' else REST_RIGHT * MIRROR


class ArmPath:
    """Solve an arm's joint angles along a sequence of tool-point positions.

    Args:
        side: 'left' or 'right'.
    """

    def __init__(self, side):
        self.side = side
        self._arm = arm_kinematics(side)
        self.lower, self.upper = joint_bounds(side)
        self._rest = np.clip(rest_posture(side), self.lower, self.upper)
        mirror = MIRROR if side == 'left' else 1.0
        self._seeds = [self._rest] + [np.clip(np.array(seed) * mirror, self.lower, self.upper)
                                      for seed in NS_MAP_SEEDS]

    def _solve(self, xyz, q, iterations):
        """Return (angles, position miss m): Gauss-Newton on the weighted least squares of the
        position, the orientation and the distance from the rest posture, from q."""
        for _ in range(iterations):
            pose, jacobian = self._arm.forward(q)
            error = np.concatenate([xyz - pose[:3, 3], ORIENTATION_WEIGHT_M * rotation_error(
                DOWN, pose[:3, :3]), REST_WEIGHT_M * (self._rest - q)])
            rows = np.vstack([jacobian[:3], ORIENTATION_WEIGHT_M * jacobian[3:],
                              REST_WEIGHT_M * np.eye(7)])
            step = np.linalg.solve(rows.T @ rows + DAMPING ** 2 * np.eye(7), rows.T @ error)
            norm = np.linalg.norm(step)
            if norm > MAX_STEP_RAD:
                step *= MAX_STEP_RAD / norm
            q = np.clip(q + step, self.lower, self.upper)
            if norm < CONVERGED_RAD:
                break
        return q, np.linalg.norm(xyz - self._arm.forward(q)[0][:3, 3])

    def solve(self, positions):
        """Return (N, 7) joint angles (rad) reaching (N, 3) tool-point positions (m, base):
        solved at every KEY_STRIDE-th position and the last, linearly in between (smooth hand
        motion sampled at 50 Hz is solved at 10 Hz: five times faster).

        Raises:
            PathError: a solved position is not reached within REACHED_M inside the bounds.
        """
        positions = np.asarray(positions, dtype=float)
        keys = np.unique(np.append(np.arange(0, len(positions), KEY_STRIDE), len(positions) - 1))
        solved = self._solve_each(positions[keys])
        steps = np.arange(len(positions))
        return np.column_stack([np.interp(steps, keys, solved[:, j]) for j in range(7)])

    def _solve_each(self, positions):
        """Return (N, 7) joint angles reaching each of the (N, 3) positions, each solve seeded
        with the last solution."""
        for seed in self._seeds:
            q, miss = self._solve(positions[0], seed.copy(), FIRST_ITERATIONS)
            if miss <= 1e-3:
                break
        path = []
        for i, xyz in enumerate(positions):
            if i and not np.array_equal(xyz, positions[i - 1]):   # a hold keeps its angles
                q, miss = self._solve(xyz, q, NEXT_ITERATIONS)
                if miss > REACHED_M:
                    q, miss = self._solve(xyz, q, FIRST_ITERATIONS)
            if miss > REACHED_M:
                raise PathError('%s arm cannot reach %s within its limits (%.1f mm short)'
                                % (self.side, np.round(xyz, 3).tolist(), miss * 1e3))
            path.append(q.copy())
        return np.array(path)
