"""Keep-out zones on following arms' commands: the cut and which zone holds which arm back (pure).

Each command of a following arm that a zone binds is cut where its motion from the last command
would enter a zone (world.zones.ZoneGuard.slide); the hit that cut it names the zone and link
until a command goes out uncut or the arm stops following. teleop_state's detail and its
zone_left / zone_right fields come from here.
"""
from robopuppet.interface import BAXTER_SIDES

ZONE_HELD = "held back by keep-out zone '%s' (%s)"   # the detail while a zone cuts commands


class ZoneHolds:
    """Cut commands at keep-out zones and remember the hit per arm.

    Args:
        guards: {side: world.zones.ZoneGuard} of the arms that keep-out zones bind.
    """

    def __init__(self, guards):
        self.guards = guards or {}
        self.hits = {side: None for side in BAXTER_SIDES}  # side -> the hit holding it, None

    def cut(self, side, before, command):
        """Return command (7 rad) cut where its motion from `before` would enter a zone."""
        if side not in self.guards:
            return command
        command, self.hits[side] = self.guards[side].slide(before, command)
        return command

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
        return '; '.join(ZONE_HELD % (hit.zone, hit.link)
                         for hit in (self.hits[s] for s in BAXTER_SIDES) if hit is not None)
