"""The ghost's joint angles: each Baxter arm where a puppet would take it (pure, time passed in).

Which puppet an arm shows, in order:
  1. a live puppet whose teleop_state says that arm follows it;
  2. the live puppet on that arm's side (puppet L: Baxter's left), copied;
  3. the live puppet on the other side, mirrored (joints 0, 2, 4, 6 negated).
So with two puppets each shows its own side; with one puppet both arms show it, the other side
mirrored, as that puppet's follow buttons would move them. Angles are clamped to Baxter's limits
exactly as arm/ commands them (arm.joint_motion's mirror and clamp).

A puppet is live while its joint states keep coming (at most timeout_s apart) and each of its
joints has sent a finite angle; a non-finite angle leaves that joint at its last finite one, as
arm/ does. An arm without a live puppet does not pretend: it takes the real arm's angles, so the
ghost arm sinks into the real one. Joints no puppet drives (head, torso, grippers) take the real
robot's values. Joints whose value is unknown (no /robot/joint_states yet) are left out.

The calibration target ghost uses the same rules with the calibration wizard's targets in place
of the puppets' angles (on_target): a target counts as live while it keeps coming, so the target
ghost sinks into the real robot when no calibration runs.
"""
import math
import reprlib

from robopuppet.arm.joint_motion import clamp, mirror
from robopuppet.arm.readings import joint_angles
from robopuppet.baxter_description import arm_joint_names
from robopuppet.interface import BAXTER_SIDE, BAXTER_SIDES, PUPPET_SIDES
from robopuppet.settings import JOINT_NAMES

REAL = 'real'  # source of an arm without a live puppet


class GhostPose:
    """Map the puppets' angles onto the ghost Baxter's joints.

    Args:
        limits: {'left': 7 limits, 'right': 7 limits} (rad; see baxter_description.arm_limits).
        movable: names of the robot's movable joints, the real robot's names.
        timeout_s: a puppet without joint states for longer than this is not live.
        prefix: put before each joint name published (see ghost_urdf).
    """

    def __init__(self, limits, movable, timeout_s, prefix):
        self.limits = limits
        self.movable = frozenset(movable)
        self.timeout_s = timeout_s
        self.prefix = prefix
        self.angles = {p: [None] * 7 for p in PUPPET_SIDES}  # newest finite angle (rad)
        self.state_t = {p: None for p in PUPPET_SIDES}       # time of the newest joint states
        self.follows = {p: () for p in PUPPET_SIDES}         # Baxter arms following puppet p
        self.real = {}                                       # {real joint name: rad or m}

    def on_puppet(self, t, side, names, positions):
        """Take puppet side's joint_states (names joint_0..joint_6, rad) at time t (s).

        Returns:
            '' or a warning: the message was refused (wrong names) or had non-finite angles.
        """
        try:
            angles = joint_angles(names, positions)
        except ValueError as error:
            return 'puppet %s joint_states ignored: %s' % (side, error)
        self.state_t[side] = t
        bad = []
        for j, angle in enumerate(angles):
            if math.isfinite(angle):
                self.angles[side][j] = angle
            else:
                bad.append(j)
        return ('puppet %s joint_states: non-finite joint %s keeps its last finite angle'
                % (side, ', '.join(map(str, bad)))) if bad else ''

    def on_target(self, t, side, names, positions):
        """Take puppet side's calibration target at time t (s): Baxter's joint names of the arm
        on that side (e.g. right_s0..right_w2 for R) and their angles (rad), taken as that
        puppet's angles; returns '' or a warning like on_puppet."""
        arm_names = arm_joint_names(BAXTER_SIDE[side])
        if len(names) != len(positions) or not set(arm_names) <= set(names):
            return ('calibration target %s ignored: needs %s with one position each, got %s'
                    % (side, ', '.join(arm_names), reprlib.repr(list(names))))  # garbage: cut
        by_name = dict(zip(names, positions))
        return self.on_puppet(t, side, JOINT_NAMES, [by_name[n] for n in arm_names])

    def on_teleop(self, side, follow_left, follow_right):
        """Take puppet side's teleop_state: which Baxter arms follow it."""
        self.follows[side] = tuple(s for s, f in zip(BAXTER_SIDES, (follow_left, follow_right))
                                   if f)

    def on_robot(self, names, positions):
        """Take Baxter's /robot/joint_states (rad or m).

        Returns:
            '' or a warning: names and positions differ in number (ignored), or joints with a
            non-finite value (those keep their last value).
        """
        if len(names) != len(positions):
            return '/robot/joint_states ignored: %d names but %d positions' % (
                len(names), len(positions))
        bad = []
        for name, value in zip(names, positions):
            if name not in self.movable:
                continue
            if math.isfinite(value):
                self.real[name] = float(value)
            else:
                bad.append(name)
        return ('/robot/joint_states: non-finite %s keep their last value' % ', '.join(bad)
                if bad else '')

    def live(self, t, side):
        """Return whether puppet side is live at time t (s): fresh data, every joint valid."""
        state_t = self.state_t[side]
        return (state_t is not None and t - state_t <= self.timeout_s and
                None not in self.angles[side])

    def sources(self, t):
        """Return {Baxter side: puppet side it shows, or REAL} at time t (s)."""
        live = [p for p in PUPPET_SIDES if self.live(t, p)]
        sources = {}
        for arm in BAXTER_SIDES:
            own = [p for p in live if BAXTER_SIDE[p] == arm]
            ranked = ([p for p in own if arm in self.follows[p]] +
                      [p for p in live if arm in self.follows[p]] + own + live)
            sources[arm] = ranked[0] if ranked else REAL
        return sources

    def arm_angles(self, arm, puppet):
        """Return Baxter arm's 7 angles (rad) for puppet's newest angles, mapped as arm/ maps
        them: copied on the puppet's own side, mirrored on the other, clamped to the limits."""
        angles = self.angles[puppet]
        return clamp(angles if BAXTER_SIDE[puppet] == arm else mirror(angles), self.limits[arm])

    def joint_states(self, t):
        """Return (names, positions) of the ghost's joints at time t (s), names prefixed; both
        empty when nothing is known yet."""
        values = dict(self.real)
        for arm, source in self.sources(t).items():
            if source != REAL:
                values.update(zip(arm_joint_names(arm), self.arm_angles(arm, source)))
        names = sorted(values)
        return [self.prefix + n for n in names], [values[n] for n in names]
