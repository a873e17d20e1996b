"""camera: a USB/V4L2 webcam (or a video file) as JPEG on /cameras/<name>/image/compressed."""
import threading
import time

import rospy
from diagnostic_msgs.msg import DiagnosticStatus, KeyValue

from robopuppet.cameras import jpeg, node_loops, webcam
from robopuppet.cameras.camera_topics import CameraTopics
from robopuppet.cameras.capture import Capture
from robopuppet.cameras.frame_rates import FrameRates

DIAG_CAMERA = 'camera'  # the status name: '<node>: camera <name>'


class CameraNode:
    """Publish a webcam's frames at ~rate as JPEG with a CameraInfo; survive a missing device.

    A missing or unplugged device is logged (throttled), reported on /diagnostics (ERROR,
    naming the device) and opened again with a growing pause (webcam.Retry); the node never
    exits for it. Each image is stamped with the time its frame was grabbed and has exactly
    ~width x ~height pixels (resized when the device delivers another size).

    Publishes: /cameras/<name>/image/compressed (sensor_msgs/CompressedImage, JPEG,
        format jpeg.JPEG_FORMAT), /cameras/<name>/camera_info (sensor_msgs/CameraInfo, same
        stamp, an ideal pinhole of ~hfov_deg), /diagnostics (1 Hz: '<node>: camera <name>',
        hardware_id the device; OK while streaming, ERROR while the device is missing).
    Parameters (webcam.DEFAULTS): ~name (str, room_camera), ~device (str or int, /dev/video0:
        a V4L2 device, its index, or a video file played in a loop), ~width and ~height (int,
        640 x 480 pixels), ~rate (float, 15 Hz), ~quality (int 1..100, 80), ~hfov_deg (float,
        60 degrees), ~frame_id (str, <name>_optical_frame).
    """

    def __init__(self, settings):
        self.settings = s = settings
        self._name = rospy.get_name()
        model = webcam.camera_model(s.width, s.height, s.hfov_deg)
        self._topics = CameraTopics(s.name, dict(model._asdict(), distortion_model='plumb_bob'),
                                    queue_size=2)
        self._retry = webcam.Retry(first_s=0.5, max_s=2.0)  # a replugged webcam: back in 2 s
        self._lock = threading.Lock()  # _retry and _jpeg_bytes, read by the diagnostics loop
        self._capture, self._streaming, self._jpeg_bytes = None, False, 0
        self._rates = FrameRates(['published'], time.monotonic())

    def run(self):
        """Capture and publish until shutdown."""
        node_loops.spin('camera', self.settings.rate_hz, self._tick, self._diagnose,
                        self._release)

    def _release(self):
        if self._capture is not None:
            self._capture.release()

    def _tick(self):
        if self._capture is None and not self._open():
            return
        problem = self._capture.grab()
        stamp = rospy.Time.now()  # the frame's capture time: grab() waited for it
        frame = None if problem else self._capture.retrieve()
        if frame is None:
            self._capture.release()
            self._capture = None
            self._failed(problem or 'the device delivered an unreadable frame')
            return
        s = self.settings
        data = jpeg.encode(jpeg.fit(frame, s.width, s.height), s.quality)
        self._topics.publish(stamp, s.frame_id, packed=data)
        self._rates.add('published')
        with self._lock:
            self._jpeg_bytes = len(data)
        if not self._streaming:
            self._first_frame()

    def _open(self):
        """Try to open the device if a retry is due; return True when it is open."""
        if not self._retry.due(time.monotonic()):
            return False
        device = self.settings.device
        problem = webcam.missing(device)
        if not problem:
            capture = Capture(device)
            if capture.opened():
                if not webcam.is_file(device):
                    capture.configure(self.settings.width, self.settings.height,
                                      self.settings.rate_hz)
                self._capture, self._streaming = capture, False
                return True
            capture.release()
            problem = 'cannot be opened as a camera or video'
        self._failed(problem)
        return False

    def _first_frame(self):
        """The device delivers: reset the retries and say so."""
        self._streaming = True
        with self._lock:
            failures = self._retry.succeeded()
        s = self.settings
        rospy.loginfo('%s: camera %s streams from %s (%dx%d at %g Hz, JPEG quality %d)%s',
                      self._name, s.name, webcam.describe(s.device), s.width, s.height,
                      s.rate_hz, s.quality,
                      ' after %d failed attempts' % failures if failures else '')

    def _failed(self, problem):
        with self._lock:
            line = self._retry.failed(time.monotonic(), '%s: %s' % (
                webcam.describe(self.settings.device), problem))
        if line is not None:
            rospy.logerr('%s: camera %s: %s', self._name, self.settings.name, line)

    def _diagnose(self):
        counts, per_s = self._rates.read(time.monotonic())
        published, rate_hz = counts['published'], per_s['published']
        with self._lock:
            size, reason = self._jpeg_bytes, self._retry.reason
            failures, delay_s = self._retry.failures, self._retry.delay_s
        s = self.settings
        if reason:
            level, message = DiagnosticStatus.ERROR, 'no images: %s; retrying in %.1f s' % (
                reason, delay_s)
        elif not self._streaming:
            level, message = DiagnosticStatus.WARN, 'opening %s' % webcam.describe(s.device)
        else:
            level, message = DiagnosticStatus.OK, 'streaming %dx%d at %.1f frames/s' % (
                s.width, s.height, rate_hz)
        values = [('device', webcam.describe(s.device)), ('frames published', str(published)),
                  ('rate_hz', '%.1f' % rate_hz), ('jpeg_bytes', str(size)),
                  ('failed attempts', str(failures))]
        return DiagnosticStatus(
            level=level, name='%s: %s %s' % (self._name, DIAG_CAMERA, s.name), message=message,
            hardware_id=str(s.device), values=[KeyValue(k, v) for k, v in values])


def main():
    """Run the camera node until shutdown (a bad parameter ends it with a clear message)."""
    rospy.init_node('camera')
    try:
        settings = webcam.read_settings(lambda name, default: rospy.get_param('~' + name,
                                                                              default))
    except ValueError as error:
        rospy.logfatal('camera cannot start: %s', error)
        raise SystemExit(1)
    CameraNode(settings).run()
