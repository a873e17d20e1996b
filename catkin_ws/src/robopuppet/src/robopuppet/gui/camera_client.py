"""The camera pane's ROS side: one camera's image/compressed at a time, decoded off the GUI thread.

No Qt here: the subscriber's callback (a rospy thread) decodes each JPEG into the FrameSlot of
its subscription; the GUI thread reads the newest frame once per frame (camera_pane).
"""
import math
import threading

import rospy
from sensor_msgs.msg import CompressedImage

from robopuppet import interface
from robopuppet.gui import camera_view

KNOWN_CAMERAS = (interface.ROOM_CAMERA,) + interface.BAXTER_CAMERAS
BUFFER_BYTES = 2 ** 24  # rospy's default 64 KiB receive buffer delays larger messages
WARN_EVERY_S = 10.0  # undecodable images: one log line per this interval at most


class CameraClient:
    """Subscribe to one camera at a time, and list the cameras the master knows.

    Subscribes: /cameras/<camera>/image/compressed (sensor_msgs/CompressedImage, JPEG) of the
        chosen camera only, and only between subscribe() and unsubscribe(); an undecodable
        image is counted and logged (throttled), never raised.
    Asks the master (on a thread of its own): the published topics, for camera_list().
    """

    def __init__(self, clock=rospy.get_time, known=KNOWN_CAMERAS):
        self._clock = clock
        self._known = tuple(known)
        self._lock = threading.Lock()
        self._subscriber = None
        self._lister = None
        self._cameras = None
        self.camera = None
        self.slot = None  # the FrameSlot of the current subscription
        self.subscribed_s = None
        self._warned_s = -math.inf

    def now(self):
        """Return the current ROS time in s (the time base of the images' stamps)."""
        return self._clock()

    def subscribe(self, camera):
        """Show `camera` from now on: drop any other subscription and start a fresh FrameSlot."""
        self.unsubscribe()
        self.slot = camera_view.FrameSlot()
        self.camera, self.subscribed_s = camera, self._clock()
        self._subscriber = self._subscribe(camera, self.slot)

    def unsubscribe(self):
        """Stop receiving images (the pane is hidden or changes camera); keep the last slot."""
        if self._subscriber is not None:
            self._subscriber.unregister()
            self._subscriber = None
        self.subscribed_s = None

    def subscribed(self):
        """Return True while a camera's images are subscribed."""
        return self._subscriber is not None

    def request_camera_list(self):
        """Ask the master for the published cameras on a thread (the call may block)."""
        with self._lock:
            if self._lister is not None and self._lister.is_alive():
                return
            self._lister = threading.Thread(target=self._list, name='camera list', daemon=True)
            self._lister.start()

    def camera_list(self):
        """Return the latest [(camera, published)] (camera_view.camera_list), or None before
        the master first answered."""
        with self._lock:
            return self._cameras

    def _subscribe(self, camera, slot):
        """Return a subscriber (anything with unregister()) that feeds _on_image."""
        return rospy.Subscriber(interface.camera_topic(camera, interface.CAMERA_COMPRESSED),
                                CompressedImage, self._on_image, (camera, slot), queue_size=1,
                                buff_size=BUFFER_BYTES)

    def _published_topics(self):
        """Return the master's [(topic, type)] (blocks; rospy.ROSException, OSError)."""
        return rospy.get_published_topics()

    def _list(self):
        try:
            topics = self._published_topics()
        except (OSError, rospy.ROSException) as error:
            rospy.logwarn_throttle(30.0, 'camera pane: cannot list the topics: %s', error)
            topics = []
        cameras = camera_view.camera_list(topics, self._known)
        with self._lock:
            self._cameras = cameras

    def _on_image(self, msg, args):
        camera, slot = args
        received_s = self._clock()
        try:
            image = camera_view.decode(msg.data)
        except ValueError as error:
            slot.put_bad(str(error))
            if received_s - self._warned_s >= WARN_EVERY_S:  # throttled on the client's clock
                self._warned_s = received_s
                rospy.logwarn('camera pane: an image of %s dropped (%d so far): %s', camera,
                              slot.bad, error)
            return
        slot.put(image, msg.header.stamp.to_sec(), received_s)
