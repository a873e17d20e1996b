"""sim_cameras: the Baxter stand-in's cameras, rendered, on Baxter's camera topics."""
import os
import threading
import time

import rospkg
import rospy
from sensor_msgs.msg import JointState
from visualization_msgs.msg import MarkerArray

from robopuppet import baxter_description as bd, interface, shape_markers
from robopuppet.cameras import (camera_services, camera_topics, marker_shapes, node_loops, scene,
                                sim_cameras)
from robopuppet.cameras.frame_rates import FrameRates
from robopuppet.world import obstacles as obstacle_files


class SimCameraNode:
    """Render each streaming camera that someone watches, at its rate; publish nothing else.

    Baxter's cameras stream while open (the hand cameras from the start at ~width x ~height and
    ~rate; /cameras/list, open and close: camera_services), room cameras always. A camera is
    rendered only while its image or image/compressed has a subscriber, not before the first
    good joint state, and again only when the joints or the task objects moved (the same frame
    is published again with a new stamp). Garbage joint states are logged (throttled) and
    ignored; a failed frame is logged and the next one comes as usual.

    Subscribes: /robot/joint_states (sensor_msgs/JointState), /robopuppet/study_task (the
    study's task markers: their cubes, spheres and cylinders are drawn, marker_shapes).
    Publishes, per streaming camera <name> of ~cameras, with one stamp per frame:
        /cameras/<name>/image (sensor_msgs/Image, bgr8), /cameras/<name>/image/compressed
        (sensor_msgs/CompressedImage, JPEG, format jpeg.JPEG_FORMAT), /cameras/<name>/camera_info
        (sensor_msgs/CameraInfo: an ideal pinhole matching the image; frame_id the URDF's
        camera frame, or <name>_optical_frame for a room camera);
        /tf_static (base -> <name>_optical_frame of each room camera);
        /robopuppet/room (visualization_msgs/MarkerArray, latched, once: the world file's shapes
        and the obstacles, muted, for RViz; published by main());
        /diagnostics (1 Hz: '<node>: simulated cameras', frames/s rendered and published).
    Parameters (sim_cameras.DEFAULTS): ~rate (float, 15 Hz), ~width, ~height (int, 640 x 480
        pixels), ~quality (int 1..100, 80), ~cameras (list, room_camera, left_hand_camera,
        right_hand_camera; head_camera too if asked), ~world_file (str, the package's
        config/world.yaml), ~obstacles_file (str, unset: config/obstacles.yaml, '': none, as
        baxter_sim's), drawn when it exists, ~zones_file (str, '': none; arm_X's keep-out
        zones), ~nice (int 0..19, 10: added to the node's nice value, so that under a full CPU
        its frames slow down before the stand-in's and the arm controllers' loops do);
        /robot_description (URDF text; the package's urdf/baxter.urdf when unset).
    """

    def __init__(self, settings, core):
        self.settings, self.core = settings, core
        self._name = rospy.get_name()
        self._services = camera_services.CameraServices(core, settings)
        self._lock = threading.Lock()  # _joints, between the callback and the render loop
        self._joints, self._objects, self._shown = None, None, {}
        self._rates = FrameRates([(name, what) for name in core.cameras
                                  for what in ('rendered', 'published')], time.monotonic())
        self._broadcaster = camera_topics.broadcast_fixed_frames(
            {c.frame_id: c.pose for c in core.cameras.values() if c.link is None})
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on_joints, queue_size=1)
        rospy.Subscriber(interface.STUDY_MARKERS, MarkerArray, self._on_markers, queue_size=10)

    def run(self):
        """Render and publish until shutdown."""
        node_loops.spin('render', camera_services.loop_rate_hz(self.settings), self._tick,
                        self._diagnose)

    def _on_joints(self, msg):
        with self._lock:
            self._joints = (list(msg.name), list(msg.position))

    def _on_markers(self, msg):
        with self._lock:
            self._objects = list(marker_shapes.apply_markers(self._shown, msg.markers).values())

    def _tick(self):
        with self._services.lock:  # a service call changes the topics
            self._frame(self._services.topics(time.monotonic()))

    def _frame(self, due):
        watched = {n: ways for n, ways in ((n, t.watched()) for n, t in due.items()) if any(ways)}
        if not watched:
            return
        with self._lock:
            joints, self._joints = self._joints, None
            objects, self._objects = self._objects, None
        if objects is not None:
            self.core.set_objects(objects)
        if joints is not None:
            try:
                self.core.set_positions(sim_cameras.check_positions(*joints))
            except ValueError as error:
                rospy.logwarn_throttle(10.0, '%s: ignored %s: %s', self._name,
                                       interface.ROBOT_JOINT_STATES, error)
        if not self.core.posed:  # no pose to draw yet: no picture rather than a wrong one
            rospy.logwarn_throttle(10.0, '%s: waiting for %s', self._name,
                                   interface.ROBOT_JOINT_STATES)
            return
        for name, (raw, packed) in watched.items():
            self.core.render(name)
            stamp = rospy.Time.now()
            raw, packed, new = self.core.encode(name, raw, packed, self.settings.quality)
            if new:
                self._rates.add((name, 'rendered'))
            due[name].publish(stamp, self.core.cameras[name].frame_id, raw, packed)
            self._rates.add((name, 'published'))

    def _diagnose(self):
        return node_loops.render_status(self._name, self.core.cameras,
                                        self._rates.read(time.monotonic())[1])

def _optional_shapes(path):
    """Return the shapes of an optional obstacle or zone file; log why a malformed one is not
    drawn (the cameras go on without it)."""
    found, problem = scene.optional_shapes(path)
    if problem:
        rospy.logerr('%s: not drawing %s: %s', rospy.get_name(), path, problem)
    return found


def main():
    """Run the simulated cameras until shutdown (bad parameters or files end it, clearly)."""
    rospy.init_node('sim_cameras')
    try:
        settings = sim_cameras.read_settings(lambda name, default: rospy.get_param(
            '~' + name, default))
        # Pictures matter less than the stand-in's and the arm controllers' timing.
        os.nice(settings.nice)
        package_dir = rospkg.RosPack().get_path('robopuppet')
        world_file = settings.world_file or os.path.join(package_dir, 'config', 'world.yaml')
        world = scene.load_world(world_file)
        obstacles = _optional_shapes(obstacle_files.chosen_path(settings.obstacles_file,
                                                                package_dir))
        zones = _optional_shapes(settings.zones_file or None)
        urdf_text = rospy.get_param(interface.ROBOT_DESCRIPTION_PARAM, None) or \
            bd.read_urdf(bd.urdf_path(package_dir))
        core = sim_cameras.SimCameras(urdf_text, world, settings.width, settings.height,
                                      settings.cameras, obstacles, zones)
    except (OSError, ValueError) as error:
        rospy.logfatal('sim_cameras cannot start: %s', error)
        raise SystemExit(1)
    rospy.loginfo('%s: %s at %dx%d, up to %g frames/s each while watched; %s, %d obstacles, '
                  '%d zones', rospy.get_name(), ', '.join(settings.cameras), settings.width,
                  settings.height, settings.rate_hz, world_file, len(obstacles), len(zones))
    room = rospy.Publisher(interface.ROOM_MARKERS, MarkerArray, queue_size=1, latch=True)
    room.publish(shape_markers.room_markers(shape_markers.room_shapes(world.shapes, obstacles),
                                            rospy.Time.now()))
    SimCameraNode(settings, core).run()
