"""The simulated cameras of the Baxter stand-in's world: settings, camera models and frames.

Baxter's own cameras (interface.BAXTER_CAMERAS) ride on the URDF's camera frames, posed by the
joint positions; the room camera(s) stand where the world file puts them. Each is an ideal
pinhole (no distortion) whose CameraInfo matches the rendered image exactly. Pure: no ROS; the
OpenGL context is made on the first render, in the thread that renders (gl_renderer).
"""
import collections
import math
import reprlib

from robopuppet import interface, params
from robopuppet.cameras import image_params, meshes, robot_shapes, scene

# ~parameter -> default (docs/cameras.md and the node's docstring list the same)
DEFAULTS = {
    'rate': 15.0,        # Hz: frames per camera per second while someone watches it
    'width': 640,        # pixels of every camera's image
    'height': 480,
    'quality': 80,       # JPEG quality 1..100 of image/compressed
    'cameras': list(interface.SIM_CAMERAS),
    'world_file': '',    # '' means the package's config/world.yaml
    'obstacles_file': None,  # world.obstacles.chosen_path: unset config/obstacles.yaml, '' none
    'zones_file': '',    # the keep-out zones arm_X enforces (its ~zones_file), drawn translucent
                         # red; '' none, like arm_X's default
    'nice': 10,          # added to the node's nice value: pictures yield the CPU to control
}
MAX_RATE_HZ = 60.0
# Focal lengths (px) at 640 pixels wide. A real Baxter's calibrated left hand camera at 640x400
# (the central crop of its 1280x800 sensor) has fx 403.1, fy 403.9; Rethink's head camera
# CameraInfo says 410. A 640x480 image is that crop with 40 more rows above and below.
BAXTER_FOCAL_PX = {'left_hand_camera': 403.0, 'right_hand_camera': 403.0,
                   'head_camera': 410.0}
REFERENCE_WIDTH = 640
OBSTACLE_COLOUR = (0.85, 0.55, 0.15)
ZONE_RGBA = (1.0, 0.0, 0.0, 0.3)

Settings = collections.namedtuple('Settings', 'rate_hz width height quality cameras world_file '
                                              'obstacles_file zones_file nice')
Settings.__doc__ = """The node's checked parameters (see DEFAULTS; files not resolved)."""
Camera = collections.namedtuple('Camera', 'name frame_id link pose k')
Camera.__doc__ = """One simulated camera: frame_id of its images; link: the URDF frame it rides
on (None for a fixed camera); pose: its fixed 4x4 optical-frame pose in the base frame (None
for a Baxter camera); k: 3x3 intrinsics [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]."""


def read_settings(get):
    """Return the checked Settings, reading each parameter with get(name, default).

    Raises:
        ValueError: a parameter is out of range or of the wrong kind; the message names it.
    """
    raw = {name: get(name, default) for name, default in DEFAULTS.items()}
    rate_hz = params.positive('~rate', raw['rate'])
    if rate_hz > MAX_RATE_HZ:
        raise ValueError('~rate must be at most %g Hz, got %r' % (MAX_RATE_HZ, raw['rate']))
    cameras = raw['cameras']
    if not (isinstance(cameras, list) and cameras and all(
            isinstance(c, str) and c for c in cameras) and len(set(cameras)) == len(cameras)):
        raise ValueError('~cameras must be a list of different camera names, got %r'
                         % (cameras,))
    for key in ('world_file', 'obstacles_file', 'zones_file'):
        if not isinstance(raw[key], str) and not (key == 'obstacles_file' and raw[key] is None):
            raise ValueError('~%s must be a file path, got %r' % (key, raw[key]))
    nice = raw['nice']
    if isinstance(nice, bool) or not isinstance(nice, int) or not 0 <= nice <= 19:
        raise ValueError('~nice must be a whole number in 0..19, got %r' % (nice,))
    return Settings(rate_hz, image_params.pixels('width', raw['width']),
                    image_params.pixels('height', raw['height']),
                    image_params.quality(raw['quality']), list(cameras), raw['world_file'],
                    raw['obstacles_file'], raw['zones_file'], nice)


def intrinsics(focal_px, width, height):
    """Return K of a pinhole with this focal length (px) and the principal point at the image
    centre, pixel centres at whole coordinates (ROS): cx = (width - 1) / 2."""
    return [[focal_px, 0.0, (width - 1) / 2.0], [0.0, focal_px, (height - 1) / 2.0],
            [0.0, 0.0, 1.0]]


def make_cameras(names, world, width, height):
    """Return {name: Camera} for camera names: Baxter's (BAXTER_CAMERAS) or the world's.

    The head camera's frame is turned 180 degrees about its axis (URDF), so its focal lengths
    are negative: the image comes out upright, as a real Baxter's does.

    Raises:
        ValueError: a name that is neither Baxter's nor in the world file.
    """
    cameras = {}
    for name in names:
        if name in interface.BAXTER_CAMERAS:
            focal_px = BAXTER_FOCAL_PX[name] * width / REFERENCE_WIDTH
            if name == 'head_camera':
                focal_px = -focal_px
            cameras[name] = Camera(name, name, name, None, intrinsics(focal_px, width, height))
        elif name in world.cameras:
            fixed = world.cameras[name]
            focal_px = (width / 2.0) / math.tan(math.radians(fixed.hfov_deg) / 2.0)
            cameras[name] = Camera(name, '%s_optical_frame' % name, None,
                                   scene.look_at_pose(fixed.xyz, fixed.look_at),
                                   intrinsics(focal_px, width, height))
        else:
            raise ValueError('unknown camera %r: not one of Baxter\'s (%s) nor in the world '
                             'file (%s)' % (name, ', '.join(interface.BAXTER_CAMERAS),
                                            ', '.join(sorted(world.cameras)) or 'none'))
    return cameras


def camera_info_fields(camera, width, height):
    """Return sensor_msgs/CameraInfo's fields of a Camera (no distortion, P = [K | 0])."""
    k = camera.k
    return {'width': width, 'height': height, 'distortion_model': 'plumb_bob',
            'D': [0.0] * 5, 'K': [v for row in k for v in row],
            'R': [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            'P': [k[0][0], 0.0, k[0][2], 0.0, 0.0, k[1][1], k[1][2], 0.0, 0.0, 0.0, 1.0, 0.0]}


def check_positions(names, positions):
    """Return {name: position} of a joint state's lists.

    Raises:
        ValueError: lists of different lengths, a name that is not a string, or a position
            that is not a finite number.
    """
    if len(names) != len(positions):
        raise ValueError('%d joint names but %d positions' % (len(names), len(positions)))
    for name, value in zip(names, positions):
        if not isinstance(name, str) or isinstance(value, bool) or \
                not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError('joint %s has position %s, not a finite number'
                             % (reprlib.repr(name), reprlib.repr(value)))
    return dict(zip(names, (float(p) for p in positions)))


class SimCameras:
    """Render the stand-in's world from each camera for the newest joint positions.

    A camera's image is rendered again only after the positions changed: the same positions
    give the same pixels. render() makes a renderer (an OpenGL context) for each image size on
    its first use: call it from one thread only.

    Args:
        urdf_text: the robot description (joints, camera frames, visual shapes).
        world: a scene.World (floor, shapes, fixed cameras).
        width, height: pixels of every image until set_size changes a camera's.
        names: the cameras to render (see make_cameras).
        obstacles, zones: lists of world.shapes.Shapes, drawn opaque orange-ish and translucent red.
        renderer_factory(width, height): makes the renderer (gl_renderer.Renderer).
    Raises:
        ValueError: an unknown camera name or a description that cannot be drawn.
    """

    def __init__(self, urdf_text, world, width, height, names, obstacles=(), zones=(),
                 renderer_factory=None):
        self.width, self.height = width, height
        self.robot = robot_shapes.RobotMesh(urdf_text)
        self._world = world
        self.cameras = make_cameras(names, world, width, height)
        self.sizes = {name: (width, height) for name in self.cameras}  # (width, height) px
        missing = [c.link for c in self.cameras.values()
                   if c.link is not None and c.link not in self.robot.poser.reachable()]
        if missing:
            raise ValueError('the robot description has no camera frame %s' % missing)
        self._world_mesh = meshes.merged(
            [scene.world_mesh(world)]
            + [scene.shape_mesh(s, default=OBSTACLE_COLOUR) for s in obstacles])
        self._zones_mesh = meshes.merged(scene.shape_mesh(s) for s in zones)
        self._factory = renderer_factory
        self._renderers = {}  # (width, height) -> (renderer, version of the robot it has)
        self._positions = {}
        self.version = 0  # counts changes of the positions
        self._posed_version, self._robot_mesh, self._link_poses = None, None, None
        self._objects_mesh = meshes.merged([])   # set_objects
        self._images = {}  # camera name -> (version, image)
        self._frames = {}  # camera name -> (version, raw bytes or None, JPEG bytes or None)

    def set_positions(self, positions):
        """Take {joint: position (rad or m)} (joints not given keep theirs); return True if
        anything changed."""
        changed = {n: p for n, p in positions.items() if self._positions.get(n) != p}
        if changed:
            self._positions.update(changed)
            self.version += 1
        return bool(changed)

    @property
    def posed(self):
        """Whether any joint position came yet (before that no picture is drawn)."""
        return bool(self._positions)

    def set_objects(self, objects):
        """Draw these world.shapes Shapes (things that move: the study's task objects) from the
        next render() on, in their own colours; [] draws none."""
        self._objects_mesh = meshes.merged(
            [scene.shape_mesh(s, default=OBSTACLE_COLOUR) for s in objects])
        self.version += 1

    def set_size(self, name, width, height):
        """Make a camera's images width x height pixels from its next render() on (its
        intrinsics scale with the width, as make_cameras gives them)."""
        self.cameras[name] = make_cameras([name], self._world, width, height)[name]
        self.sizes[name] = (width, height)
        self._images.pop(name, None)
        self._frames.pop(name, None)

    def _pose_robot(self):
        if self._posed_version != self.version:
            robot_mesh, self._link_poses = self.robot.posed(self._positions)
            self._robot_mesh = meshes.merged([robot_mesh, self._objects_mesh])
            self._posed_version = self.version

    def camera_pose(self, name):
        """Return the 4x4 pose of a camera's optical frame in the base frame, now."""
        camera = self.cameras[name]
        if camera.link is None:
            return camera.pose
        self._pose_robot()
        return self._link_poses[camera.link]

    def render(self, name):
        """Return (BGR image (height, width, 3 uint8), version of the positions it shows).

        The image is the same object as long as the positions stay the same: do not modify it.
        """
        version, image = self._images.get(name, (None, None))
        if version == self.version:
            return image, version
        size = self.sizes[name]
        if size not in self._renderers:
            if self._factory is None:
                from robopuppet.cameras import gl_renderer  # OpenGL only where it renders
                self._factory = gl_renderer.Renderer
            renderer = self._factory(*size)
            renderer.set_world(self._world_mesh)
            renderer.set_zones(self._zones_mesh, ZONE_RGBA)
            self._renderers[size] = (renderer, None)  # no robot yet
        self._pose_robot()
        renderer, robot_version = self._renderers[size]
        if robot_version != self.version:
            renderer.set_robot(self._robot_mesh)
            self._renderers[size] = (renderer, self.version)
        image = renderer.render(self.camera_pose(name), self.cameras[name].k)
        self._images[name] = (self.version, image)
        return image, self.version

    def encode(self, name, raw, packed, quality):
        """Return (raw, packed, new) of a camera's last rendered image (render): raw BGR bytes
        when raw, JPEG bytes at quality when packed (else None), each made once per version;
        new: the first call for this version of the positions."""
        version, image = self._images[name]
        cached, raw_bytes, jpeg_bytes = self._frames.get(name, (None, None, None))
        new = cached != version
        if new:
            raw_bytes = jpeg_bytes = None
        if raw and raw_bytes is None:
            raw_bytes = image.tobytes()
        if packed and jpeg_bytes is None:
            from robopuppet.cameras import jpeg  # OpenCV: loaded once someone watches a camera
            jpeg_bytes = jpeg.encode(image, quality)
        self._frames[name] = (version, raw_bytes, jpeg_bytes)
        return raw_bytes if raw else None, jpeg_bytes if packed else None, new

    def close(self):
        """Release the renderers (a later render() makes new ones)."""
        for renderer, _ in self._renderers.values():
            renderer.close()
        self._renderers.clear()
        self._images.clear()
