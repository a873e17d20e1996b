"""The bounded commands of the Baxter arms arm_X drives, whoever leads them (pure).

A puppet-following arm and an arm the assist drives (arm.assist_follow) move by the same rules:
each command is clamped to the joint limits, moved by a SpeedBudget (first a slow approach from
where Baxter is, then at most the joint's velocity limit) toward the target kept on the leash
(arm.leash: within leash_s of mode-1 travel of where Baxter is now, so that Baxter coasts little
when the commands stop) and cut at the keep-out zones (arm.zone_holds); an arm that stops, or
holds, is commanded to where Baxter is now.
"""
from robopuppet.arm.joint_motion import SpeedBudget, clamp
from robopuppet.arm.leash import leashed
from robopuppet.interface import BAXTER_SIDES


class ArmDrive:
    """Command each driven arm toward its target within limits, speed and keep-out zones.

    Args:
        limits: {'left': 7 limits, 'right': 7 limits} (see baxter_description.arm_limits).
        robot: the teleop's baxter_watch.BaxterWatch (Baxter's measured poses).
        zones: the teleop's zone_holds.ZoneHolds.
        approach_speed_rad_s: joint speed while an arm closes in on its target (capped per
            joint by the joint's velocity limit).
        track_tolerance_rad: the approach ends when every joint is this close to the target.
        command_period_s: the nominal time between commands; the speed budget holds this much
            motion, so one command may carry speed x command_period_s at once.
        leash_s: each joint's target is kept within leash_s x its mode-1 speed of where Baxter
            is now (arm.leash); 0: no leash. The SpeedBudget moves the command toward that
            target, so a command pulled back (Baxter's pose jumped back) moves at the same
            speed as any other, and the zone cut sees the step from the previous command.
    Attributes:
        tracking: {side: bool}, False while the arm approaches its target.
    """

    def __init__(self, limits, robot, zones, approach_speed_rad_s, track_tolerance_rad,
                 command_period_s, leash_s=0.0):
        self.limits, self.robot, self.zones = limits, robot, zones
        self.approach_speed_rad_s = approach_speed_rad_s
        self.track_tolerance_rad = track_tolerance_rad
        self.command_period_s = command_period_s
        self.leash_s = leash_s
        self.tracking = {side: False for side in BAXTER_SIDES}
        self._motion = {}          # side -> SpeedBudget holding the last command

    def start(self, side, t):
        """Start driving Baxter's `side` arm at t from where Baxter measures it: approach."""
        self.tracking[side] = False
        self._motion[side] = SpeedBudget(clamp(self.robot.pose[side], self.limits[side]),
                                         self.command_period_s, t)

    def toward(self, side, t, angles):
        """Return the command (7 rad) sent at t that moves the arm toward `angles` (rad)."""
        target = clamp(angles, self.limits[side])
        speeds = [lim.velocity if self.tracking[side]
                  else min(self.approach_speed_rad_s, lim.velocity)
                  for lim in self.limits[side]]
        motion = self._motion[side]
        goal = leashed(target, self.robot.now(side, t), self.limits[side], self.leash_s)
        motion.command = self.zones.cut(side, t, motion.command, motion.move(goal, speeds, t))
        if max(abs(c - g) for c, g in zip(motion.command, target)) <= self.track_tolerance_rad:
            self.tracking[side] = True
        return motion.command

    def hold(self, side, t, begin):
        """Return the command (7 rad) sent at t that holds the arm still: where Baxter is now
        when the hold begins (begin True), then that pose again. Moving on approaches anew."""
        motion = self._motion[side]
        motion.command = self.zones.stay(side, t, self.robot.now(side, t) if begin
                                         else motion.command)
        self.tracking[side] = False
        return motion.command

    def stay(self, side, t):
        """Return the command (7 rad) sent at t that stops the arm where Baxter is now.

        Baxter in position mode goes on to the last command it got; commanding where it is
        stops it at once instead of after its command timeout (where it is now: BaxterWatch.now).
        """
        return self.zones.stay(side, t, self.robot.now(side, t))
