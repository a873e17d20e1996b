"""Contact of a stand-in arm with obstacles: motions stop at contact, blocked joints push.

Every model step, an arm's motion from its angles toward where it would go this step is limited
with world.zones.ZoneGuard.slide over the obstacles (every link a capsule from the URDF, checked
along the whole motion): the arm stops at the last configuration proven clear, the guard's
zones.MARGIN_M (2 mm, and up to RESOLUTION_M more) short of the obstacle; from there the parts
of a command that lead along or away from it are followed (the arm slides on a table top and
never sticks to it). A joint whose motion is still cut is blocked: it reports the torque a
stiff position servo would press with, stiffness x how far its command lies past where it
stopped, saturating at the effort limit (the URDF's, Rethink's: 50/100/50/50/15/15/15 N m;
docs/baxter_sim.md).

An arm pressing on an obstacle asks the same question every step (and at every command, which
steps the model too): from where it is held, on in the same direction. That answer is kept and
given again without the guard until the arm moves or the direction changes; holding is always
safe, so this can never let a link in. Pure: numpy, no ROS, no clock.
"""
import numpy as np

from robopuppet import baxter_description as bd
from robopuppet.interface import BAXTER_SIDES
from robopuppet.world import obstacles as obstacle_files
from robopuppet.world.arm_capsules import ArmCapsules
from robopuppet.world.zones import ZoneGuard

# A blocked joint's torque reaches its effort limit when its command lies this far past contact.
SATURATION_RAD = 0.25
MOVING_RAD = 1e-12   # a joint whose allowed motion falls short of this is cut
SAME_DIRECTION = 1e-9   # unit motions closer than this (rad) push the same way


class ArmContact:
    """Limit one arm's motions to keep it out of the obstacles; say the blocked joints' torques.

    Args:
        capsules: the arm's world.arm_capsules.ArmCapsules.
        obstacles: world.shapes.Shapes in the base frame (not empty).
        max_effort: (7,) the joints' effort limits (N m), s0 .. w2.
    """

    def __init__(self, capsules, obstacles, max_effort):
        self.guard = ZoneGuard(capsules, obstacles)
        self.max_effort = np.asarray(max_effort, np.float64)
        self.stiffness = self.max_effort / SATURATION_RAD   # N m per rad
        self._held = None   # (angles, unit motion) the guard last refused to leave at all

    def limit(self, q_from, q_to):
        """Return (q_out, blocked): how far the arm gets from q_from toward q_to (7 angles, rad)
        without a link entering an obstacle, and a (7,) bool array of the joints cut short."""
        q_from, q_to = np.asarray(q_from, np.float64), np.asarray(q_to, np.float64)
        motion = q_to - q_from
        if not motion.any():   # holding still: nothing can enter
            return q_to, np.zeros(len(q_to), bool)
        unit = motion / np.linalg.norm(motion)
        held = self._held
        if held is not None and np.array_equal(held[0], q_from) and \
                np.abs(held[1] - unit).max() < SAME_DIRECTION:
            return q_from, np.abs(motion) > MOVING_RAD
        q_out = np.asarray(self.guard.slide(q_from, q_to)[0], np.float64)
        self._held = (q_from, unit) if np.array_equal(q_out, q_from) else None
        return q_out, np.abs(q_to - q_out) > MOVING_RAD

    def press(self, push_rad):
        """Return (7,) torques (N m) of blocked joints whose commands lie push_rad (7,) past
        where they stopped: stiffness x push, within the effort limits."""
        return np.clip(self.stiffness * np.asarray(push_rad), -self.max_effort, self.max_effort)


def arm_contacts(description, urdf_text, obstacles):
    """Return {side: ArmContact} for both arms, or {} when there are no obstacles.

    Raises:
        world.arm_capsules.CapsuleError: the URDF has no usable shapes for an arm link.
    """
    if not obstacles:
        return {}
    contacts = {}
    for side in BAXTER_SIDES:
        efforts = [description.joints[n].effort for n in bd.arm_joint_names(side)]
        contacts[side] = ArmContact(ArmCapsules(description, urdf_text, side), obstacles,
                                    efforts)
    return contacts


def obstacle_contacts(value, package_dir, description, urdf_text):
    """Return (arm_contacts of an ~obstacles_file's shapes, a log line naming them).

    Args:
        value: the parameter (None: the package's default file when it exists; '': none).
        package_dir: the robopuppet package's directory.

    Raises:
        ValueError: the file cannot be used (also ObstacleFileError and CapsuleError).
    """
    if value is not None and not isinstance(value, str):
        raise ValueError('~obstacles_file must be a file path, got %r' % (value,))
    path = obstacle_files.chosen_path(value, package_dir)
    shapes = obstacle_files.load_obstacles(path) if path else []
    return arm_contacts(description, urdf_text, shapes), (
        'obstacles from %s: %s' % (path, ', '.join(s.name for s in shapes)) if shapes
        else 'no obstacles')
