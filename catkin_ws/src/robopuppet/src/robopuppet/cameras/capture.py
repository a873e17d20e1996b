"""The camera node's transport: one opened V4L2 device or video file (OpenCV's VideoCapture).

Like protocol/serial_link.py beside serial_node: I/O, no ROS. A video file goes through the same
calls as a device, so tests and demos exercise the node's real path without a webcam.
"""
import cv2

from robopuppet.cameras import webcam


class Capture:
    """One opened device or video file: grab() waits for the next frame, retrieve() decodes it.

    A video file plays in a loop. A device (or file) whose path has gone counts as unplugged:
    an open file would otherwise play on from its deleted inode.
    """

    def __init__(self, device):
        self.device = device
        what, backend = webcam.source(device)
        self._capture = cv2.VideoCapture(what, backend)

    def opened(self):
        return self._capture.isOpened()

    def configure(self, width, height, rate_hz):
        """Ask a V4L2 device for the size and rate (it may pick the nearest it has) and for one
        buffer only, so that a slow reader gets the newest frame, not a queued old one."""
        for prop, value in ((cv2.CAP_PROP_FRAME_WIDTH, width),
                            (cv2.CAP_PROP_FRAME_HEIGHT, height), (cv2.CAP_PROP_FPS, rate_hz),
                            (cv2.CAP_PROP_BUFFERSIZE, 1)):
            self._capture.set(prop, value)

    def grab(self):
        """Wait for the next frame; return '' when there is one, else why there is none."""
        gone = webcam.missing(self.device)  # unplugged: the same reason as a failed open
        if gone:
            return gone
        if self._capture.grab():
            return ''
        if webcam.is_file(self.device):  # the end of the file: play it again
            self._capture.set(cv2.CAP_PROP_POS_FRAMES, 0)
            if self._capture.grab():
                return ''
        return 'the device delivers no frames'

    def retrieve(self):
        """Return the grabbed frame (BGR numpy image) or None."""
        ok, frame = self._capture.retrieve()
        return frame if ok else None

    def release(self):
        self._capture.release()
