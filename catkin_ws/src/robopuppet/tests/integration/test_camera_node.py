#!/usr/bin/python3
"""The camera node survives a missing device, streams what the device shows at the advertised
size and JPEG quality, reports an unplugged device and recovers when it is back."""
import os
import shutil
import threading
import time
import unittest

import cv2
import numpy as np
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import CameraInfo, CompressedImage

from robopuppet import interface
from robopuppet.cameras import jpeg, webcam

from waiting import wait_for

CAMERA, NODE = 'test_camera', '/camera_test'
WIDTH, HEIGHT, QUALITY, HFOV_DEG = 320, 240, 60, 70.0
VIDEO_SIZE = (640, 480)  # the file's frames: the node must scale them to WIDTH x HEIGHT


def pattern(index):
    """Return video frame `index`: quadrants of four colours and the frame number."""
    width, height = VIDEO_SIZE
    image = np.zeros((height, width, 3), np.uint8)
    image[:height // 2, :width // 2] = (0, 0, 255)
    image[:height // 2, width // 2:] = (0, 255, 0)
    image[height // 2:, :width // 2] = (255, 0, 0)
    image[height // 2:, width // 2:] = (255, 255, 255)
    cv2.putText(image, str(index), (250, 260), cv2.FONT_HERSHEY_SIMPLEX, 3, (0, 0, 0), 6)
    return image


def write_video(path, frames=20, rate_hz=20.0):
    """Write a short MJPG video next to `path` and move it there at once (no half file seen)."""
    partial = path + '.partial.avi'
    writer = cv2.VideoWriter(partial, cv2.VideoWriter_fourcc(*'MJPG'), rate_hz, VIDEO_SIZE)
    assert writer.isOpened(), 'OpenCV cannot write %s' % partial
    for index in range(frames):
        writer.write(pattern(index))
    writer.release()
    os.rename(partial, path)


class CameraNodeTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('camera_node_test')
        cls.device = rospy.get_param('~device')
        os.makedirs(os.path.dirname(cls.device), exist_ok=True)
        cls.lock = threading.Lock()
        cls.images, cls.infos, cls.statuses, cls.errors = [], [], [], []
        rospy.Subscriber(interface.camera_topic(CAMERA, interface.CAMERA_COMPRESSED),
                         CompressedImage, cls.keep, (cls.images, 'image'), queue_size=100,
                         buff_size=2 ** 24)
        rospy.Subscriber(interface.camera_topic(CAMERA, interface.CAMERA_INFO), CameraInfo,
                         cls.keep, (cls.infos, 'info'), queue_size=100)
        rospy.Subscriber(interface.DIAGNOSTICS, DiagnosticArray, cls.on_diagnostics,
                         queue_size=100)
        rospy.Subscriber('/rosout', Log, cls.on_log, queue_size=100)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(os.path.dirname(cls.device), ignore_errors=True)

    @classmethod
    def keep(cls, msg, args):
        store, _ = args
        with cls.lock:
            store.append((time.monotonic(), rospy.get_time(), msg))

    @classmethod
    def on_diagnostics(cls, msg):
        for status in msg.status:
            if status.name == '%s: camera %s' % (NODE, CAMERA):
                with cls.lock:
                    cls.statuses.append((time.monotonic(), status))

    @classmethod
    def on_log(cls, msg):
        if msg.name == NODE and msg.level >= Log.ERROR:
            with cls.lock:
                cls.errors.append((time.monotonic(), msg.msg))

    def since(self, store, start_s):
        with self.lock:
            return [entry[1:] if len(entry) == 3 else entry[1] for entry in store
                    if entry[0] >= start_s]

    def wait_status(self, level, start_s, count=1, timeout_s=10.0):
        """Wait for `count` statuses of this level after start_s; return the newest."""
        found = wait_for(lambda: len([s for s in self.since(self.statuses, start_s)
                                      if s.level == level]) >= count, timeout_s)
        self.assertTrue(found, 'no %d statuses of level %d; got %s' % (
            count, level, [(s.level, s.message) for s in self.since(self.statuses, start_s)]))
        return [s for s in self.since(self.statuses, start_s) if s.level == level][-1]

    def check_streaming(self, start_s):
        """Check ten images (and their camera_info) that arrived after start_s."""
        self.assertTrue(wait_for(lambda: len(self.since(self.images, start_s)) >= 10, 15.0),
                        'no images after the device appeared')
        images = self.since(self.images, start_s)[:10]
        stamps = [msg.header.stamp.to_sec() for _, msg in images]
        self.assertEqual(stamps, sorted(stamps))
        for received_s, msg in images:
            self.assertLess(abs(received_s - msg.header.stamp.to_sec()), 1.0,
                            'the stamp is not the capture time')
            self.assertEqual(msg.format, jpeg.JPEG_FORMAT)
            self.assertEqual(msg.header.frame_id, 'test_camera_optical_frame')
            self.assertEqual(jpeg.quality_of(msg.data), QUALITY)
            decoded = cv2.imdecode(np.frombuffer(msg.data, np.uint8), cv2.IMREAD_COLOR)
            self.assertEqual(decoded.shape, (HEIGHT, WIDTH, 3))
        # What the file shows, scaled: compare away from the number in the middle.
        expected = cv2.resize(pattern(0), (WIDTH, HEIGHT), interpolation=cv2.INTER_AREA)
        corner = (slice(10, 50), slice(10, 300))
        difference = np.abs(decoded[corner].astype(int) - expected[corner].astype(int)).mean()
        self.assertLess(difference, 12.0)
        infos = {msg.header.stamp: msg for _, msg in self.since(self.infos, start_s)}
        info = infos.get(images[-1][1].header.stamp)
        self.assertIsNotNone(info, 'no camera_info with the image\'s stamp')
        model = webcam.camera_model(WIDTH, HEIGHT, HFOV_DEG)
        self.assertEqual((info.width, info.height), (WIDTH, HEIGHT))
        np.testing.assert_allclose(info.K, model.K)
        np.testing.assert_allclose(info.P, model.P)

    def test_missing_then_streaming_then_unplugged_then_back(self):
        # 1. Missing: the node stays, says so on /diagnostics and in one log line.
        start_s = time.monotonic()
        status = self.wait_status(DiagnosticStatus.ERROR, 0.0, count=3, timeout_s=15.0)
        self.assertIn(self.device, status.message)
        self.assertIn('no such file', status.message)
        self.assertEqual(status.hardware_id, self.device)
        attempts = int(dict((kv.key, kv.value) for kv in status.values)['failed attempts'])
        self.assertGreaterEqual(attempts, 3)  # it kept retrying ...
        errors = self.since(self.errors, 0.0)
        self.assertEqual(len(errors), 1, errors)  # ... and logged it once
        self.assertIn(self.device, errors[0])
        self.assertEqual(self.since(self.images, 0.0), [])
        # 2. The device appears: streaming at the advertised size and quality.
        appeared_s = time.monotonic()
        write_video(self.device)
        self.check_streaming(appeared_s)
        status = self.wait_status(DiagnosticStatus.OK, appeared_s)
        self.assertIn('streaming 320x240', status.message)
        rospy.loginfo('camera streamed %.1f s after the file appeared (missing for %.1f s)',
                      time.monotonic() - appeared_s, appeared_s - start_s)
        # 3. Unplugged: reported again, images stop.
        unplugged_s = time.monotonic()
        os.rename(self.device, self.device + '.away')
        status = self.wait_status(DiagnosticStatus.ERROR, unplugged_s)
        self.assertIn(self.device, status.message)
        self.assertTrue(wait_for(lambda: any(self.device in text for text in self.since(
            self.errors, unplugged_s)), 5.0), 'the unplugged device was not logged')
        quiet_s = time.monotonic() + 0.5
        time.sleep(1.5)
        self.assertEqual(self.since(self.images, quiet_s), [])
        # 4. Plugged in again: streaming again.
        back_s = time.monotonic()
        os.rename(self.device + '.away', self.device)
        self.check_streaming(back_s)


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'camera_node', CameraNodeTest)
