"""The RViz marker as a study device: a 6-DOF interactive marker on the gripper's tool point."""
import time

import numpy as np
import rospy
from geometry_msgs.msg import Point, Pose, Quaternion
from interactive_markers.interactive_marker_server import InteractiveMarkerServer
from interactive_markers.menu_handler import MenuHandler
from visualization_msgs.msg import (InteractiveMarker, InteractiveMarkerControl,
                                    InteractiveMarkerFeedback, Marker)

from robopuppet import baxter_description, interface

MARKER = 'gripper'
MENU = ('Follow / stop', 'Close gripper', 'Open gripper')   # entries 1, 2, 3
RESET_PERIOD_S = 0.5   # while the arm does not follow, the marker returns to the gripper this often
AXES = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def _marker(xyz, quaternion):
    """Return the interactive marker: a box to grab and a move and rotate control per axis."""
    marker = InteractiveMarker(name=MARKER, description='gripper', scale=0.2)
    marker.header.frame_id = baxter_description.BASE_FRAME
    marker.pose = _pose(xyz, quaternion)
    box = Marker(type=Marker.CUBE)
    box.scale.x = box.scale.y = box.scale.z = 0.05
    box.color.r, box.color.g, box.color.b, box.color.a = 0.9, 0.6, 0.1, 0.8
    marker.controls.append(InteractiveMarkerControl(
        interaction_mode=InteractiveMarkerControl.MENU, always_visible=True, markers=[box]))
    for (x, y, z), name in zip(AXES, 'xyz'):
        for mode in (InteractiveMarkerControl.MOVE_AXIS, InteractiveMarkerControl.ROTATE_AXIS):
            control = InteractiveMarkerControl(name='%s_%s' % (mode, name), interaction_mode=mode)
            # a control's axis is its orientation's x axis: rotate x onto the wanted axis
            control.orientation = Quaternion(*_axis_quaternion(x, y, z))
            marker.controls.append(control)
    return marker


def _axis_quaternion(x, y, z):
    """Return the quaternion (x, y, z, w) that turns the x axis onto a unit axis of base."""
    if y:
        return (0.0, 0.0, 0.7071068, 0.7071068)
    if z:
        return (0.0, -0.7071068, 0.0, 0.7071068)
    return (0.0, 0.0, 0.0, 1.0)


def _pose(xyz, quaternion):
    return Pose(position=Point(*xyz), orientation=Quaternion(*quaternion))


class MarkerDevice:
    """Serve interface.marker_server(side) and turn its feedback into the device core's inputs.

    Menu 1 is one follow press, 2 closes and 3 opens the gripper; each POSE_UPDATE is solved
    (cartesian.CartesianArm.solve, seeded with the target) into the target while the arm
    follows; an unreachable pose leaves the target and sets the marker back on the gripper.

    Args:
        side: 'L' or 'R'; core: its device_core.DeviceCore; arm: its cartesian.CartesianArm;
        lock: the lock every core call is made under.
    """

    def __init__(self, side, core, arm, lock):
        self._core, self._arm, self._lock = core, arm, lock
        self._server = InteractiveMarkerServer(interface.marker_server(side))
        self._menu = MenuHandler()
        for title, take in zip(MENU, (self._on_follow, self._on_close, self._on_open)):
            self._menu.insert(title, callback=take)
        self._shown, self._next_reset_s = None, 0.0
        self._server.insert(_marker((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)), self._on_feedback,
                            InteractiveMarkerFeedback.POSE_UPDATE)
        self._menu.apply(self._server, MARKER)
        self._server.applyChanges()
        # interactive_markers refuses a client's feedback within 1 s of another client's, and
        # counts the marker's creation as one: lifted, so that the first click counts.
        context = self._server.marker_contexts.get(MARKER)
        if context is not None:
            context.last_feedback = rospy.Time(0)

    def _on_follow(self, feedback):
        rospy.loginfo('%s: marker menu: follow / stop', rospy.get_name())
        with self._lock:
            self._core.press_follow(time.monotonic())

    def _on_close(self, feedback):
        rospy.loginfo('%s: marker menu: close gripper', rospy.get_name())
        with self._lock:
            self._core.set_closed(True)

    def _on_open(self, feedback):
        rospy.loginfo('%s: marker menu: open gripper', rospy.get_name())
        with self._lock:
            self._core.set_closed(False)

    def _on_feedback(self, feedback):
        p, o = feedback.pose.position, feedback.pose.orientation
        with self._lock:
            seed = self._core.target()
            solution = None if seed is None else self._arm.solve(
                (p.x, p.y, p.z), (o.x, o.y, o.z, o.w), seed)
            taken = solution is not None and self._core.set_target(solution)
        if not taken:
            self._show(seed, force=True)
        else:   # the pose the server took: every other RViz shows the marker where it went
            self._server.applyChanges()

    def _show(self, q, force=False):
        """Put the marker on the gripper's tool point at angles q (when it moved or forced)."""
        if q is None:
            return
        xyz, rotation = self._arm.tip(q)
        if not force and self._shown is not None and np.allclose(xyz, self._shown, atol=1e-3):
            return
        self._shown = xyz
        self._server.setPose(MARKER, _pose(xyz, baxter_description.matrix_quaternion(rotation)))
        self._server.applyChanges()

    def step(self, now):
        """Set the marker back on the gripper now and then while the arm does not follow."""
        if now < self._next_reset_s:
            return
        self._next_reset_s = now + RESET_PERIOD_S
        with self._lock:
            following, target = self._core.following(), self._core.target()
        if not following:
            self._show(target)
