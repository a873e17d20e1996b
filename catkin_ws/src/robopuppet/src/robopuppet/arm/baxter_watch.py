"""What Baxter's /robot/joint_states tell arm_X: a believable pose per arm and where it is (pure).

Time is an argument. A pose that is not finite, or is further than ROBOT_POSE_MARGIN_RAD outside
the URDF's limits, is not Baxter's (garbage on the topic) and is ignored, so such a value never
becomes a puppet setpoint or a command.
"""
import math

from robopuppet.arm.joint_motion import all_finite, clamp

# Baxter reports its joints slightly past the URDF limits at a limit; a pose further out than
# this is not Baxter's and is ignored.
ROBOT_POSE_MARGIN_RAD = 0.1
# Where Baxter is now is its newest measured pose moved on by its measured velocity for the age
# of the measurement, but never by more than this much time.
MAX_EXTRAPOLATION_S = 0.05


class BaxterWatch:
    """Keep the newest believable pose and velocity of each of Baxter's arms.

    Args:
        limits: {'left': 7 limits, 'right': 7 limits}, each with lower, upper (rad) and
            velocity (rad/s), in puppet joint order (see baxter_description.arm_limits).
    """

    def __init__(self, limits):
        self.limits = limits
        self.pose = {}           # side -> 7 angles (rad)
        self._motion = {}        # side -> (measurement time s, 7 velocities rad/s)
        self.ignored_poses = 0   # arm poses not believed (non-finite, out of limits)

    def on_robot_pose(self, t, pose, velocities=None):
        """Take {side: 7 joint angles rad} of Baxter's arms, measured at time t.

        An arm pose that is not believable is ignored and counted (the previous pose stays).
        velocities ({side: 7 rad/s}, where known) tell where the arm is a little later; one
        that is not finite or beyond the joint's velocity limit counts as 0.
        """
        velocities = velocities or {}
        for side, angles in pose.items():
            limits = self.limits[side]
            if all_finite(angles) and all(
                    lim.lower - ROBOT_POSE_MARGIN_RAD <= a <= lim.upper + ROBOT_POSE_MARGIN_RAD
                    for a, lim in zip(angles, limits)):
                self.pose[side] = list(angles)
                speeds = velocities.get(side) or [0.0] * len(angles)
                self._motion[side] = (t, [
                    v if math.isfinite(v) and abs(v) <= lim.velocity else 0.0
                    for v, lim in zip(speeds, limits)])
            else:
                self.ignored_poses += 1

    def pose_age(self, side, t):
        """Return how old (s) the believable pose of Baxter's arm on `side` is at time t, or
        None when none came."""
        if side not in self.pose:
            return None
        return t - self._motion[side][0]

    def measured(self, side):
        """Return (measured at s, 7 angles rad, 7 velocities rad/s) of Baxter's arm on `side`,
        the newest believable measurement (None when none came)."""
        if side not in self.pose:
            return None
        measured_t, speeds = self._motion[side]
        return measured_t, list(self.pose[side]), list(speeds)

    def now(self, side, t):
        """Return where Baxter's arm on `side` is at time t, within its limits, or None if unknown.

        The measured pose moved on by the measured velocity for the measurement's age (at most
        MAX_EXTRAPOLATION_S), since the arm moved on while the measurement travelled.
        """
        if side not in self.pose:
            return None
        measured_t, speeds = self._motion[side]
        age_s = min(max(t - measured_t, 0.0), MAX_EXTRAPOLATION_S)
        return clamp([a + v * age_s for a, v in zip(self.pose[side], speeds)], self.limits[side])
