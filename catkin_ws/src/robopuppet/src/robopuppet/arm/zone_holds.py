"""Keep-out zones on following arms' commands: the cut and which zone holds which arm back (pure).

Each command of a following arm that a zone binds is cut so that the arm's motion, from wherever
Baxter can be (arm_reach: its measured pose and the commands on their way) to the command, is
proven clear of every zone (world.zones.ZoneGuard.limit_box); the hit that cut it names the zone
and link until a command goes out uncut or the arm stops following. A stay command (the arm
stops following) targets where Baxter is, moved into that box. teleop_state's detail and its
zone_left / zone_right fields come from here.
"""
from robopuppet.arm.arm_reach import ArmReach
from robopuppet.interface import BAXTER_SIDES
from robopuppet.world.zones import Hit

ZONE_HELD = "held back by keep-out zone '%s' (%s)"   # the detail while a zone cuts commands
# ... and while Baxter's pose is too old to prove anything (ArmReach.where: None)
POSE_TOO_OLD = Hit('', "held still: Baxter's joint states are too old to keep it out of the "
                       'keep-out zones')


class ZoneHolds:
    """Cut commands at keep-out zones and remember the hit per arm.

    Args:
        guards: {side: world.zones.ZoneGuard} of the arms that keep-out zones bind.
        robot: the arm_X's baxter_watch.BaxterWatch (Baxter's measured poses).
    """

    def __init__(self, guards, robot):
        self.guards = guards or {}
        self.robot = robot
        self.reach = {side: ArmReach() for side in self.guards}
        self.hits = {side: None for side in BAXTER_SIDES}  # side -> the hit holding it, None

    def cut(self, side, t, before, command):
        """Return command (7 rad), sent at t after `before`, cut so that Baxter's motion to it
        keeps out of every zone."""
        if side not in self.guards:
            return command
        box = self.reach[side].where(t, *self.robot.measured(side))
        if box is None:   # the previous command again: its box was proven when it was sent
            command, self.hits[side] = list(before), POSE_TOO_OLD
        else:
            command, self.hits[side] = self.guards[side].limit_box(*box, before, command)
        self.reach[side].sent(t, command)
        return command

    def stay(self, side, t, pose):
        """Return the command (7 rad) sent at t that stops the arm at `pose`, where Baxter is:
        moved into the box where the arm can be, so that its last motion stays in it."""
        if side not in self.guards:
            return pose
        pose = self.reach[side].inside(pose)
        self.reach[side].sent(t, pose)
        return pose

    def holding(self):
        """Return whether a zone holds any arm back."""
        return any(hit is not None for hit in self.hits.values())

    def forget(self, following):
        """Forget the hits of the arms that do not follow ({side: bool})."""
        for side in BAXTER_SIDES:
            if not following[side]:
                self.hits[side] = None

    def zone(self, side):
        """Return the name of the zone holding Baxter's `side` arm back, '' when none does."""
        hit = self.hits[side]
        return '' if hit is None else hit.zone

    def detail(self):
        """Return the detail that names each zone and link holding an arm back, '' none."""
        return '; '.join(ZONE_HELD % (hit.zone, hit.link) if hit.zone else hit.link
                         for hit in (self.hits[s] for s in BAXTER_SIDES) if hit is not None)
