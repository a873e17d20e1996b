"""One Baxter arm as capsules (segment + radius), posed by the URDF's forward kinematics.

Every link below <side>_arm_mount (shoulder to gripper fingertips) that has primitive geometry in
the URDF becomes capsules, one per shape: a cylinder is the segment along its axis with its
radius; a box, the segment along its longest side with the half diagonal of its cross-section as
radius; a sphere, a point with its radius. Each capsule contains its shape. A link's <collision>
shapes are used when it has any, else its <visual> ones (robopuppet's URDF has visuals only, the
same shapes RViz and the simulated cameras draw). A link below a prismatic joint (the gripper
fingers) is taken at the middle of the joint's travel with every radius grown by half the travel,
so that its capsules hold it at any gripper opening.

The pose of every capsule comes from the same joint origins and axes as
baxter_description.Description.transform (and robot_state_publisher), batched over many
configurations with numpy. Pure: numpy, no ROS.
"""
import numpy as np

from robopuppet import baxter_description as bd
from robopuppet.world import shapes


class CapsuleError(ValueError):
    """The robot description has no usable shapes for an arm link."""


def _capsule(shape):
    """Return ((end 1, end 2) in the link frame, radius) of the capsule holding a Shape."""
    pose = shapes.shape_pose(shape)
    if shape.type == 'cylinder':
        radius, axis = shape.radius, pose[:3, 2] * shape.length / 2.0
    elif shape.type == 'box':
        size = np.array(shape.size)
        longest = int(np.argmax(size))
        radius = float(np.hypot(*np.delete(size, longest))) / 2.0
        axis = pose[:3, longest] * size[longest] / 2.0
    else:
        radius, axis = shape.radius, np.zeros(3)
    return (pose[:3, 3] - axis, pose[:3, 3] + axis), radius


def link_capsules(urdf_text):
    """Return {link: [((end 1, end 2) m in the link frame, radius m), ...]} of every link with
    primitive shapes (collision ones if it has any, else visual ones).

    Raises:
        CapsuleError: the text is not XML, or a shape is malformed.
    """
    try:
        found = shapes.link_shapes(urdf_text, ('collision', 'visual'))
    except shapes.ShapeFileError as error:
        raise CapsuleError(str(error)) from None
    return {link: [_capsule(shape) for shape in parts] for link, parts in found.items()}


class ArmCapsules:
    """The capsules of one Baxter arm, posed for batches of its 7 joint angles.

    Args:
        description: a baxter_description.Description.
        urdf_text: the same description's URDF text (for its shapes).
        side: 'left' or 'right'.

    Attributes:
        links: the link name of each capsule (C of them).
        radii: (C,) capsule radii (m).
        half_lengths: (C,) half the length of each capsule's segment (m).
        reach: (C, 7) bound on how far (m) any point of each capsule's segment is from each arm
            joint's axis, whatever the angles (0 for joints after its link): a capsule's segment
            moves at most reach @ |dq| for a joint-space motion dq along a straight line.

    Raises:
        CapsuleError: an arm link below the mount has no primitive shape, or a joint that is
            not one of the arm's 7 moves it.
    """

    def __init__(self, description, urdf_text, side):
        self.side = side
        names = bd.arm_joint_names(side)
        mount = '%s_arm_mount' % side
        self._mount = description.transform({}, mount)
        shapes = link_capsules(urdf_text)
        # Frames: 0 the mount, 1 + j the child link of arm joint j; every other link below the
        # mount sits at a fixed transform from one of them (prismatic joints at mid-travel).
        self._origins = np.empty((7, 4, 4))
        self._axes = np.empty((7, 3))
        frame_of = {mount: (0, np.eye(4), 0.0)}   # link -> (frame, link-in-frame, radius growth)
        pending = [j for j in description.joints.values() if j.parent != j.child]
        while True:
            ready = [j for j in pending if j.parent in frame_of and j.child not in frame_of]
            if not ready:
                break
            for joint in ready:
                frame, pose, grow = frame_of[joint.parent]
                if joint.type in ('revolute', 'continuous'):
                    if joint.name not in names:
                        raise CapsuleError('joint %r moves the arm but is not one of %s'
                                           % (joint.name, names))
                    j = names.index(joint.name)
                    if frame != j:
                        raise CapsuleError('joint %r is not after joint %r in the chain'
                                           % (joint.name, names[j - 1] if j else mount))
                    self._origins[j], self._axes[j] = pose @ joint.origin, joint.axis
                    frame_of[joint.child] = (j + 1, np.eye(4), grow)
                    continue
                step = joint.origin.copy()
                if joint.type == 'prismatic':
                    step[:3, 3] += step[:3, :3] @ joint.axis * (joint.lower + joint.upper) / 2.0
                    grow += (joint.upper - joint.lower) / 2.0
                frame_of[joint.child] = (frame, pose @ step, grow)
        missing = [n for n in names if description.joints[n].child not in frame_of]
        if missing:
            raise CapsuleError('arm joints %s are not below %r' % (missing, mount))
        links, frames, ends, radii = [], [], [], []
        # Capsules in frame order (the links of one frame as found), so that segments() can
        # pose each frame's capsules with one product and join them in order.
        for link, (frame, pose, grow) in sorted(frame_of.items(), key=lambda item: item[1][0]):
            for (end_1, end_2), radius in shapes.get(link, []):
                links.append(link)
                frames.append(frame)
                ends.append([pose[:3, :3] @ end + pose[:3, 3] for end in (end_1, end_2)])
                radii.append(radius + grow)
        if not links:
            raise CapsuleError('no arm link below %r has a primitive shape' % mount)
        self.links = links
        self.radii = np.array(radii)
        self._frames = np.array(frames)
        # Per frame with capsules: its capsules' ends as homogeneous columns (end 1, end 2, ...).
        columns = np.concatenate([np.array(ends), np.ones((len(ends), 2, 1))], axis=2)
        self._ends = {f: columns[self._frames == f].reshape(-1, 4).T.copy()
                      for f in sorted(set(frames))}
        self.half_lengths = np.linalg.norm(np.subtract(*np.array(ends).transpose(1, 0, 2)),
                                           axis=1) / 2.0
        self.reach = self._reach(np.array(ends))
        # Joint j's child frame in its parent's is origin_j @ turn(angle): Rodrigues' turn,
        # I + sin K + (1 - cos) K^2, is fixed + sin by_sin + cos by_cos with these (7, 4, 4).
        k = np.zeros((7, 4, 4))
        k[:, :3, :3] = [[[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]]
                        for a in self._axes]
        self._fixed = self._origins @ (np.eye(4) + k @ k)
        self._by_sin, self._by_cos = self._origins @ k, -(self._origins @ k @ k)
        for table in (self._fixed, self._by_sin, self._by_cos):   # joint 0 from the base frame
            table[0] = self._mount @ table[0]

    def _reach(self, ends):
        """Return the (C, 7) reach bound: from joint j's axis to a point in frame f > j, at most
        the distance along the chain's origins j+1 .. f-1 plus the point's distance from frame
        f's origin (measured from frame f's own axis when f = j + 1, which is exact)."""
        offsets = np.linalg.norm(self._origins[:, :3, 3], axis=1)  # joint j's origin in frame j
        reach = np.zeros((len(ends), 7))
        for c, frame in enumerate(self._frames):
            for j in range(frame):   # joints 0 .. frame-1 move frame `frame`
                if j == frame - 1:
                    radial = ends[c] - np.outer(ends[c] @ self._axes[j], self._axes[j])
                    reach[c, j] = np.linalg.norm(radial, axis=1).max()
                else:
                    reach[c, j] = offsets[j + 1:frame].sum() + \
                        np.linalg.norm(ends[c], axis=1).max()
        return reach

    def segments(self, angles):
        """Return (M, C, 3, 2): both ends (m, base frame; last axis: end 1, end 2) of every
        capsule's segment for (M, 7) joint angles (rad)."""
        angles = np.asarray(angles, np.float64)[..., None, None]
        local = self._fixed + np.sin(angles) * self._by_sin + np.cos(angles) * self._by_cos
        parts = []
        if 0 in self._ends:   # capsules fixed to the mount (Baxter's arms have none)
            fixed = self._mount[:3] @ self._ends[0]
            parts.append(np.broadcast_to(fixed, local.shape[:1] + fixed.shape))
        frame = local[:, 0, :3]   # (M, 3, 4): rows x, y, z of joint 0's child link in base
        for f in range(1, 8):     # the chain: one product per joint, on all M at once
            if f > 1:
                frame = frame @ local[:, f - 1]
            if f in self._ends:
                parts.append(frame @ self._ends[f])
        joined = np.concatenate(parts, axis=2)                             # (M, 3, 2 C)
        return joined.reshape(len(joined), 3, -1, 2).transpose(0, 2, 1, 3)
