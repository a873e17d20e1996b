#!/usr/bin/python3
"""camera_republish turns a raw camera's images (Baxter's bgra8) into JPEG with the same header,
and drops an image it cannot convert without stopping."""
import threading
import unittest

import cv2
import numpy as np
import rospy
import rostest
from sensor_msgs.msg import CompressedImage, Image

from robopuppet import interface
from robopuppet.cameras import jpeg
from waiting import wait_for

CAMERA = 'test_hand_camera'
WIDTH, HEIGHT = 640, 400  # Baxter's hand cameras' default size


def bgra_image(stamp, shade):
    """Return a bgra8 sensor_msgs/Image: left half blue, right half of grey `shade`."""
    pixels = np.zeros((HEIGHT, WIDTH, 4), np.uint8)
    pixels[:, :WIDTH // 2] = (255, 0, 0, 255)
    pixels[:, WIDTH // 2:] = (shade, shade, shade, 255)
    msg = Image(height=HEIGHT, width=WIDTH, encoding='bgra8', step=WIDTH * 4,
                data=pixels.tobytes())
    msg.header.stamp, msg.header.frame_id = stamp, 'right_hand_camera'
    return msg


class CameraRepublishTest(unittest.TestCase):

    def test_raw_images_come_out_as_jpeg_with_their_header(self):
        rospy.init_node('camera_republish_test')
        received, lock = [], threading.Lock()

        def keep(msg):
            with lock:
                received.append(msg)
        jpegs = rospy.Subscriber(interface.camera_topic(CAMERA, interface.CAMERA_COMPRESSED),
                                 CompressedImage, keep, queue_size=10)
        raw = rospy.Publisher(interface.camera_topic(CAMERA, interface.CAMERA_IMAGE), Image,
                              queue_size=10)
        wait_for(lambda: raw.get_num_connections() and jpegs.get_num_connections(), 20.0,
                 'camera_republish connected both ways')
        stamps = []
        for count, shade in enumerate((40, 120, 200), 1):
            bad = Image(height=2, width=2, encoding='yuv422', step=4, data=bytes(8))
            raw.publish(bad)  # dropped with a warning; the node goes on
            stamps.append(rospy.Time.now())
            raw.publish(bgra_image(stamps[-1], shade))
            wait_for(lambda: len(received) >= count, 10.0, 'JPEG number %d' % count)
        with lock:
            got = list(received)
        self.assertEqual([msg.header.stamp for msg in got], stamps)
        for msg, shade in zip(got, (40, 120, 200)):
            self.assertEqual(msg.header.frame_id, 'right_hand_camera')
            self.assertEqual(msg.format, jpeg.JPEG_FORMAT)
            self.assertEqual(jpeg.quality_of(msg.data), 70)
            image = cv2.imdecode(np.frombuffer(msg.data, np.uint8), cv2.IMREAD_COLOR)
            self.assertEqual(image.shape, (HEIGHT, WIDTH, 3))
            np.testing.assert_allclose(image[HEIGHT // 2, WIDTH // 4], (255, 0, 0), atol=6)
            np.testing.assert_allclose(image[HEIGHT // 2, 3 * WIDTH // 4], (shade,) * 3, atol=6)


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'camera_republish_test', CameraRepublishTest)
