"""A camera's topics: image (raw, when asked for), image/compressed (JPEG) and camera_info, each
frame with one stamp; and the static frames of fixed cameras."""
import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import CameraInfo, CompressedImage, Image

from robopuppet import baxter_description as bd, interface


class CameraTopics:
    """Publish one camera's frames.

    Publishes: /cameras/<name>/image (sensor_msgs/Image, bgr8; only when raw),
        /cameras/<name>/image/compressed (sensor_msgs/CompressedImage, JPEG, format
        jpeg.JPEG_FORMAT), /cameras/<name>/camera_info (sensor_msgs/CameraInfo of info_fields).

    Args:
        name: the camera's name.
        info_fields: {field: value} of its CameraInfo (width, height, K, ...).
        raw: whether it has an image topic too.
        queue_size: of each publisher.
    """

    def __init__(self, name, info_fields, raw=False, queue_size=1):
        def publisher(what, kind):
            return rospy.Publisher(interface.camera_topic(name, what), kind,
                                   queue_size=queue_size)
        self._raw = publisher(interface.CAMERA_IMAGE, Image) if raw else None
        self._packed = publisher(interface.CAMERA_COMPRESSED, CompressedImage)
        self._info_pub = publisher(interface.CAMERA_INFO, CameraInfo)
        self._info = CameraInfo(**info_fields)

    def watched(self):
        """Return (raw, packed): whether anyone subscribes to the image, image/compressed."""
        return (self._raw is not None and self._raw.get_num_connections() > 0,
                self._packed.get_num_connections() > 0)

    def publish(self, stamp, frame_id, raw=None, packed=None):
        """Publish a frame: raw BGR bytes (or None: not), JPEG bytes (or None: not), and the
        CameraInfo, all with this stamp and frame_id."""
        if raw is not None:
            info = self._info
            msg = Image(height=info.height, width=info.width, encoding='bgr8', is_bigendian=0,
                        step=info.width * 3, data=raw)
            msg.header.stamp, msg.header.frame_id = stamp, frame_id
            self._raw.publish(msg)
        if packed is not None:
            from robopuppet.cameras import jpeg  # OpenCV: loaded once someone watches a camera
            msg = CompressedImage(format=jpeg.JPEG_FORMAT, data=packed)
            msg.header.stamp, msg.header.frame_id = stamp, frame_id
            self._packed.publish(msg)
        self._info.header.stamp, self._info.header.frame_id = stamp, frame_id
        self._info_pub.publish(self._info)

    def unregister(self):
        """Withdraw the topics (a closed Baxter camera has none)."""
        for pub in (self._raw, self._packed, self._info_pub):
            if pub is not None:
                pub.unregister()


def broadcast_fixed_frames(poses):
    """Send {frame: 4x4 pose in Baxter's base frame} on /tf_static; return the broadcaster,
    which must be kept (its latched publisher goes with it)."""
    broadcaster = tf2_ros.StaticTransformBroadcaster()
    transforms = []
    for frame, pose in poses.items():
        t = TransformStamped()
        t.header.stamp, t.header.frame_id = rospy.Time.now(), bd.BASE_FRAME
        t.child_frame_id = frame
        t.transform.translation.x, t.transform.translation.y, \
            t.transform.translation.z = pose[:3, 3]
        r = t.transform.rotation
        r.x, r.y, r.z, r.w = bd.matrix_quaternion(pose[:3, :3])
        transforms.append(t)
    if transforms:
        broadcaster.sendTransform(transforms)
    return broadcaster
