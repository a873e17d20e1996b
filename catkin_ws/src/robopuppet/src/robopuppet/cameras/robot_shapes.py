"""Baxter as the simulated cameras see it: the URDF's visual shapes, posed by its joints.

The shapes are the URDF's own <visual> boxes, cylinders and spheres (the ones RViz shows), one
merged mesh per link in the link's frame; poses come from baxter_description's forward
kinematics, so the cameras, RViz and the stand-in agree on where every link is. Pure: XML and
numpy, no ROS.
"""
import xml.etree.ElementTree as ET

import numpy as np

from robopuppet import baxter_description as bd
from robopuppet.cameras import meshes

DEFAULT_COLOUR = (0.6, 0.6, 0.6)  # a visual without a material colour


class ShapeError(ValueError):
    """A visual of the robot description cannot be drawn."""


def _colour(visual, named):
    material = visual.find('material')
    if material is None:
        return DEFAULT_COLOUR
    colour = material.find('color')
    if colour is not None:
        return tuple(bd.floats(colour.get('rgba'), '', 4)[:3])
    return named.get(material.get('name'), DEFAULT_COLOUR)


def _geometry_mesh(geometry, colour):
    """Return the mesh of a URDF <geometry>, or None for a mesh file (not drawn)."""
    for shape in geometry:
        if shape.tag == 'box':
            return meshes.box(bd.floats(shape.get('size'), '', 3), colour)
        if shape.tag == 'cylinder':
            return meshes.cylinder(float(shape.get('radius')), float(shape.get('length')),
                                   colour)
        if shape.tag == 'sphere':
            return meshes.sphere(float(shape.get('radius')), colour)
        if shape.tag == 'mesh':
            return None
        raise ValueError('unknown geometry <%s>' % shape.tag)
    raise ValueError('empty <geometry>')


def link_meshes(urdf_text):
    """Return {link name: Mesh in the link's frame} of the URDF's visual boxes, cylinders and
    spheres (links without any are left out; mesh files are skipped).

    Raises:
        ShapeError: the text is not XML, or a visual has a malformed geometry or origin.
    """
    try:
        root = ET.fromstring(urdf_text)
    except ET.ParseError as error:
        raise ShapeError('robot description is not XML: %s' % error) from error
    named = {}
    for material in root.findall('material'):
        colour = material.find('color')
        if colour is not None:
            named[material.get('name')] = tuple(bd.floats(colour.get('rgba'), '', 4)[:3])
    result = {}
    for link in root.findall('link'):
        parts = []
        for visual in link.findall('visual'):
            try:
                geometry = visual.find('geometry')
                if geometry is None:
                    raise ValueError('no <geometry>')
                mesh = _geometry_mesh(geometry, _colour(visual, named))
                if mesh is not None:
                    parts.append(meshes.transformed(mesh, bd.origin_matrix(visual)))
            except (TypeError, ValueError) as error:
                raise ShapeError('link %r: visual: %s' % (link.get('name'), error)) from None
        if parts:
            result[link.get('name')] = meshes.merged(parts)
    return result


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
        ShapeError, baxter_description.DescriptionError: the description cannot be drawn.
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
