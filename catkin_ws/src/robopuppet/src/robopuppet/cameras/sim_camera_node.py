"""sim_cameras: the Baxter stand-in's cameras, rendered, on Baxter's camera topics."""
import os
import threading
import time

import rospkg
import rospy
import tf2_ros
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import CameraInfo, CompressedImage, Image, JointState
from visualization_msgs.msg import MarkerArray

from robopuppet import baxter_description as bd, interface, shape_markers
from robopuppet.cameras import node_loops, scene, sim_cameras
from robopuppet.world import obstacles as obstacle_files


class SimCameraNode:
    """Render each camera that someone watches at ~rate; publish nothing for the others.

    A camera is rendered only while its image or image/compressed topic has a subscriber, not
    before the first good joint state, and again only when the joint positions changed (still
    positions give the same pixels, which are published again with a new stamp). Garbage joint
    states are logged (throttled) and ignored; a failed frame is logged and the next one comes
    as usual.

    Subscribes: /robot/joint_states (sensor_msgs/JointState).
    Publishes, per camera <name> of ~cameras, with one stamp per frame:
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
        baxter_sim's), drawn when it exists, ~zones_file (str, '': none; arm_X's keep-out zones), ~nice (int
        0..19, 10: added to the node's nice value, so that under a full CPU its frames slow
        down before the stand-in's and the arm controllers' loops do); /robot_description
        (URDF text; the package's urdf/baxter.urdf when unset).
    """

    def __init__(self, settings, core):
        self.settings, self.core = settings, core
        self._name = rospy.get_name()
        self._pubs = {}
        for name in core.cameras:
            self._pubs[name] = tuple(
                rospy.Publisher(interface.camera_topic(name, what), kind, queue_size=1)
                for what, kind in (('image', Image), ('image/compressed', CompressedImage),
                                   ('camera_info', CameraInfo)))
        self._diag_pub = rospy.Publisher(interface.DIAGNOSTICS, DiagnosticArray, queue_size=10)
        self._lock = threading.Lock()  # _joints (callback) and the counters (diagnostics)
        self._joints = None
        self._rendered = dict.fromkeys(core.cameras, 0)
        self._published = dict.fromkeys(core.cameras, 0)
        self._last = (time.monotonic(), dict(self._rendered), dict(self._published))
        self._cache = {}  # camera -> (version, raw bytes or None, JPEG bytes or None)
        self._broadcaster = tf2_ros.StaticTransformBroadcaster()
        self._broadcast_fixed_frames()
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on_joints, queue_size=1)

    def run(self):
        """Render and publish until shutdown."""
        node_loops.spin('render', self.settings.rate_hz, self._tick, self._diagnose)

    def _broadcast_fixed_frames(self):
        transforms = []
        for camera in self.core.cameras.values():
            if camera.link is None:
                t = TransformStamped()
                t.header.stamp, t.header.frame_id = rospy.Time.now(), bd.BASE_FRAME
                t.child_frame_id = camera.frame_id
                t.transform.translation.x, t.transform.translation.y, \
                    t.transform.translation.z = camera.pose[:3, 3]
                r = t.transform.rotation
                r.x, r.y, r.z, r.w = bd.matrix_quaternion(camera.pose[:3, :3])
                transforms.append(t)
        if transforms:
            self._broadcaster.sendTransform(transforms)

    def _on_joints(self, msg):
        with self._lock:
            self._joints = (list(msg.name), list(msg.position))

    def _tick(self):
        watched = [n for n, (raw, packed, _) in self._pubs.items()
                   if raw.get_num_connections() or packed.get_num_connections()]
        if not watched:
            return
        with self._lock:
            joints, self._joints = self._joints, None
        if joints is not None:
            try:
                self.core.set_positions(sim_cameras.check_positions(*joints))
            except ValueError as error:
                rospy.logwarn_throttle(10.0, '%s: ignored %s: %s', self._name,
                                       interface.ROBOT_JOINT_STATES, error)
        if self.core.version == 0:  # no pose to draw yet: no picture rather than a wrong one
            rospy.logwarn_throttle(10.0, '%s: waiting for %s', self._name,
                                   interface.ROBOT_JOINT_STATES)
            return
        for name in watched:
            self._publish(name)

    def _publish(self, name):
        raw_pub, packed_pub, info_pub = self._pubs[name]
        image, version = self.core.render(name)
        stamp = rospy.Time.now()
        cached, raw, packed = self._cache.get(name, (None, None, None))
        if cached != version:
            raw = packed = None
            with self._lock:
                self._rendered[name] += 1
        s, frame_id = self.settings, self.core.cameras[name].frame_id
        if raw_pub.get_num_connections():
            raw = raw if raw is not None else image.tobytes()
            msg = Image(height=s.height, width=s.width, encoding='bgr8', is_bigendian=0,
                        step=s.width * 3, data=raw)
            msg.header.stamp, msg.header.frame_id = stamp, frame_id
            raw_pub.publish(msg)
        if packed_pub.get_num_connections():
            from robopuppet.cameras import jpeg  # OpenCV: loaded once someone watches a camera
            packed = packed if packed is not None else jpeg.encode(image, s.quality)
            msg = CompressedImage(format=jpeg.JPEG_FORMAT, data=packed)
            msg.header.stamp, msg.header.frame_id = stamp, frame_id
            packed_pub.publish(msg)
        self._cache[name] = (version, raw, packed)
        info = CameraInfo(**sim_cameras.camera_info_fields(self.core.cameras[name], s.width,
                                                           s.height))
        info.header.stamp, info.header.frame_id = stamp, frame_id
        info_pub.publish(info)
        with self._lock:
            self._published[name] += 1

    def _diagnose(self):
        now_s = time.monotonic()
        with self._lock:
            rendered, published = dict(self._rendered), dict(self._published)
        then_s, then_rendered, then_published = self._last
        self._last = (now_s, rendered, published)
        span_s = max(now_s - then_s, 1e-3)
        values, lines = [], []
        for name in self.core.cameras:
            render_hz = (rendered[name] - then_rendered[name]) / span_s
            publish_hz = (published[name] - then_published[name]) / span_s
            values += [KeyValue('%s rendered_hz' % name, '%.1f' % render_hz),
                       KeyValue('%s published_hz' % name, '%.1f' % publish_hz)]
            if publish_hz > 0.0:
                lines.append('%s %.1f/s' % (name, publish_hz))
        array = DiagnosticArray(status=[DiagnosticStatus(
            level=DiagnosticStatus.OK, name='%s: simulated cameras' % self._name,
            message='publishing ' + ', '.join(lines) if lines else 'nobody watches',
            hardware_id='simulated', values=values)])
        array.header.stamp = rospy.Time.now()
        self._diag_pub.publish(array)


def _package_file(path, folder, default_name):
    return path or os.path.join(rospkg.RosPack().get_path('robopuppet'), folder, default_name)


def _shapes_if_present(path):
    """Return the shapes of an optional obstacle or zone file: [] when it does not exist, and
    [] with an error logged when it is malformed (the cameras go on without them)."""
    if path is None or not os.path.exists(path):
        return []
    try:
        return scene.load_world(path).shapes
    except scene.SceneError as error:
        rospy.logerr('%s: not drawing %s: %s', rospy.get_name(), path, error)
        return []


def _urdf_text():
    text = rospy.get_param('/robot_description', None)
    if text:
        return text
    with open(bd.urdf_path(rospkg.RosPack().get_path('robopuppet'))) as urdf:
        return urdf.read()


def main():
    """Run the simulated cameras until shutdown (bad parameters or files end it, clearly)."""
    rospy.init_node('sim_cameras')
    try:
        settings = sim_cameras.read_settings(lambda name, default: rospy.get_param(
            '~' + name, default))
        # Pictures matter less than the stand-in's and the arm controllers' timing.
        os.nice(settings.nice)
        world_file = _package_file(settings.world_file, 'config', 'world.yaml')
        world = scene.load_world(world_file)
        obstacles = _shapes_if_present(obstacle_files.chosen_path(
            settings.obstacles_file, rospkg.RosPack().get_path('robopuppet')))
        zones = _shapes_if_present(settings.zones_file or None)
        core = sim_cameras.SimCameras(_urdf_text(), world, settings.width, settings.height,
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
