"""Baxter as the simulated cameras see it: the URDF's visual shapes, posed by its joints.

The shapes are the URDF's own <visual> boxes, cylinders and spheres (the ones RViz shows), one
merged mesh per link in the link's frame; poses come from baxter_description's forward
kinematics, so the cameras, RViz and the stand-in agree on where every link is. Pure: numpy, no
ROS.
"""
import numpy as np

from robopuppet import baxter_description as bd
from robopuppet.cameras import meshes, scene
from robopuppet.world import shapes

DEFAULT_COLOUR = (0.6, 0.6, 0.6)  # a visual without a material colour


def link_meshes(urdf_text):
    """Return {link name: Mesh in the link's frame} of the URDF's visual boxes, cylinders and
    spheres (world.shapes.link_shapes; links without any are left out).

    Raises:
        world.shapes.ShapeFileError: the text is not XML, or a visual is malformed.
    """
    return {link: meshes.merged([scene.shape_mesh(shape, DEFAULT_COLOUR) for shape in parts])
            for link, parts in shapes.link_shapes(urdf_text, ('visual',)).items()}


class RobotPoser:
    """Poses of every link of a description for given joint positions, in its base frame.

    Args:
        description: a baxter_description.Description.
    """

    def __init__(self, description, base=bd.BASE_FRAME):
        self.description = description
        self.base = base
        self._order = []  # joints parent-first: a link's pose is its parent's times the joint
        done = {base}
        pending = list(description.joints.values())
        while pending:
            ready = [j for j in pending if j.parent in done]
            if not ready:
                break  # links not below base: no pose
            for joint in ready:
                self._order.append(joint)
                done.add(joint.child)
            pending = [j for j in pending if j.child not in done]
        # A fixed joint's transform does not depend on the positions: work it out once.
        self._fixed = {j.name: description.transform({}, j.child, j.parent)
                       for j in self._order if j.type == 'fixed'}

    def reachable(self):
        """Return the links that have a pose (the base and every link below it)."""
        return {self.base} | {joint.child for joint in self._order}

    def link_poses(self, positions):
        """Return {link: 4x4 pose in the base frame} for {joint name: position (rad or m)}.

        Missing joints count as 0 and mimic joints follow theirs, as in Description.transform.
        """
        poses = {self.base: np.eye(4)}
        for joint in self._order:
            step = self._fixed.get(joint.name)
            if step is None:  # one joint's own transform, by baxter_description's kinematics
                step = self.description.transform(positions, joint.child, joint.parent)
            poses[joint.child] = poses[joint.parent] @ step
        return poses


class RobotMesh:
    """The robot's visual shapes as one mesh, posed in the base frame for joint positions.

    Args:
        urdf_text: the robot description (its joints and visuals).
    Raises:
        world.shapes.ShapeFileError, baxter_description.DescriptionError: the description
            cannot be drawn.
    """

    def __init__(self, urdf_text):
        self.poser = RobotPoser(bd.Description(urdf_text))
        parts = link_meshes(urdf_text)
        self._links = sorted(link for link in parts if link in self.poser.reachable())
        whole = meshes.merged(parts[link] for link in self._links)
        self._vertices, self._normals, self.colours = whole
        self._slices, start = [], 0
        for link in self._links:
            end = start + len(parts[link].vertices)
            self._slices.append((link, slice(start, end)))
            start = end

    def posed(self, positions):
        """Return (Mesh in the base frame, {link: 4x4 pose}) for {joint: position}."""
        poses = self.poser.link_poses(positions)
        vertices = np.empty_like(self._vertices)
        normals = np.empty_like(self._normals)
        for link, part in self._slices:
            pose = poses[link].astype(np.float32)
            np.matmul(self._vertices[part], pose[:3, :3].T, out=vertices[part])
            vertices[part] += pose[:3, 3]
            np.matmul(self._normals[part], pose[:3, :3].T, out=normals[part])
        return meshes.Mesh(vertices, normals, self.colours), poses
