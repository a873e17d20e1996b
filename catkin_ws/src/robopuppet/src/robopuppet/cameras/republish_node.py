"""camera_republish: JPEG siblings (image/compressed) of raw camera topics, e.g. Baxter's own.

A real Baxter publishes sensor_msgs/Image on /cameras/<name>/image only; Debian's
image_transport has no compressed plugin, so `image_transport republish` cannot make the
compressed topic the GUI shows. This node does, for each camera named.
"""
import rospy
from sensor_msgs.msg import CompressedImage, Image

from robopuppet import interface
from robopuppet.cameras import image_params, jpeg

DEFAULT_QUALITY = 80


class Republisher:
    """Encode each raw image of the named cameras as JPEG, while someone listens.

    An image nobody subscribes to is not encoded. A raw image of an unsupported encoding or a
    wrong size is logged (throttled) and dropped; the node keeps running.

    Subscribes: /cameras/<name>/image (sensor_msgs/Image: bgr8, rgb8, bgra8, rgba8, mono8).
    Publishes: /cameras/<name>/image/compressed (sensor_msgs/CompressedImage, JPEG, the raw
        image's header).
    Parameters: ~cameras (list of str, default Baxter's head_camera, left_hand_camera,
        right_hand_camera), ~quality (int 1..100, default 80).
    """

    def __init__(self, cameras, quality):
        self.quality = quality
        self._pubs, self._subs = {}, []
        for camera in cameras:
            self._pubs[camera] = rospy.Publisher(
                interface.camera_topic(camera, interface.CAMERA_COMPRESSED), CompressedImage,
                queue_size=2)
            self._subs.append(rospy.Subscriber(
                interface.camera_topic(camera, interface.CAMERA_IMAGE), Image, self._on_image,
                camera, queue_size=1, buff_size=2 ** 24))

    def _on_image(self, msg, camera):
        pub = self._pubs[camera]
        if pub.get_num_connections() == 0:
            return
        try:
            image = jpeg.raw_to_bgr(msg.encoding, msg.width, msg.height, msg.step, msg.data)
            data = jpeg.encode(image, self.quality)
        except jpeg.JpegError as error:
            rospy.logwarn_throttle(10.0, '%s: %s dropped: %s', rospy.get_name(),
                                   interface.camera_topic(camera, interface.CAMERA_IMAGE), error)
            return
        pub.publish(CompressedImage(header=msg.header, format=jpeg.JPEG_FORMAT, data=data))


def main():
    """Run the republisher until shutdown (a bad parameter ends it with a clear message)."""
    rospy.init_node('camera_republish')
    cameras = rospy.get_param('~cameras', list(interface.BAXTER_CAMERAS))
    try:
        if not (isinstance(cameras, list) and cameras
                and all(isinstance(c, str) and c for c in cameras)):
            raise ValueError('~cameras must be a list of camera names, got %r' % (cameras,))
        quality = image_params.quality(rospy.get_param('~quality', DEFAULT_QUALITY))
    except ValueError as error:
        rospy.logfatal('camera_republish cannot start: %s', error)
        raise SystemExit(1)
    Republisher(cameras, quality)
    rospy.loginfo('%s: JPEG at quality %d of %s', rospy.get_name(), quality,
                  ', '.join(interface.camera_topic(c, interface.CAMERA_IMAGE) for c in cameras))
    rospy.spin()
