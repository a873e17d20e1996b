"""The camera pane: its pure decisions (camera_view) and the widget (pytest-qt) over a client whose
ROS parts (subscriber, master) are replaced; the callback and decoding are the real ones."""
import os

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import cv2  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import rospy  # noqa: E402
from sensor_msgs.msg import CompressedImage  # noqa: E402

from robopuppet.gui import camera_view  # noqa: E402
from robopuppet.gui.camera_client import CameraClient  # noqa: E402
from robopuppet.gui.camera_pane import CameraPane  # noqa: E402
from robopuppet.gui.look import AMBER, GREEN, RED  # noqa: E402
from robopuppet.gui.window import Window  # noqa: E402
from test_gui_widgets import FakeClient  # noqa: E402

WARN, ERROR, OK = camera_view.WARN, camera_view.ERROR, camera_view.OK
TOPICS = [('/cameras/room_camera/image/compressed', 'sensor_msgs/CompressedImage'),
          ('/cameras/room_camera/camera_info', 'sensor_msgs/CameraInfo'),
          ('/cameras/left_hand_camera/image', 'sensor_msgs/Image'),
          ('/cameras/bench/image/compressed', 'sensor_msgs/CompressedImage'),
          ('/puppet/arm_R/heartbeat', 'std_msgs/Empty')]


def jpeg_of(bgr, width=320, height=240, quality=90):
    image = np.zeros((height, width, 3), np.uint8)
    image[:] = bgr
    return cv2.imencode('.jpg', image, [cv2.IMWRITE_JPEG_QUALITY, quality])[1].tobytes()


# ---- camera_view: pure -----------------------------------------------------------------------
def frame(stamp_s, received_s):
    return camera_view.Frame(None, stamp_s, received_s, 1)


@pytest.mark.parametrize('now_s, frame_, subscribed_s, level, words', [
    (10.0, None, None, WARN, 'no camera chosen'),
    (10.0, None, 9.0, WARN, 'waiting for frames'),
    (10.0, None, 7.0, ERROR, 'no frames for 3.0 s'),
    (10.0, frame(9.95, 9.97), 0.0, OK, 'live'),
    (10.0, frame(9.5, 9.9), 0.0, WARN, 'late: the frame shown is 500 ms old'),
    (10.0, frame(8.5, 9.9), 0.0, ERROR, 'late: the frame shown is 1.5 s old'),
    (10.0, frame(9.25, 9.3), 0.0, WARN, 'stopped: no new frame for 700 ms'),
    (10.0, frame(6.9, 7.0), 0.0, ERROR, 'stopped: no new frame for 3.0 s'),
    (10.0, frame(8.8, 9.4), 0.0, ERROR, 'stopped: no new frame for 600 ms'),
    (10.0, frame(11.0, 9.99), 0.0, WARN, 'clocks synchronised'),
])
def test_the_verdict_flags_old_and_stopped_streams(now_s, frame_, subscribed_s, level, words):
    verdict = camera_view.judge(now_s, frame_, subscribed_s)
    assert verdict.level == level and words in verdict.text


def test_the_frame_slot_keeps_the_newest_and_counts_frames_per_second():
    slot = camera_view.FrameSlot(window_s=2.0)
    assert slot.newest() is None and slot.rate_hz(5.0, 0.0) == 0.0
    for i in range(40):  # 20 frames/s from t = 0 to 1.95 s
        slot.put('image %d' % i, i * 0.05 - 0.01, i * 0.05)
    newest = slot.newest()
    assert newest.image == 'image 39' and newest.seq == 40
    assert slot.rate_hz(1.96, 0.0) == pytest.approx(40 / 1.96)  # young subscription: 1.96 s
    assert slot.rate_hz(2.95, 0.0) == pytest.approx(20 / 2.0)  # half the window empty
    assert slot.rate_hz(10.0, 0.0) == 0.0
    slot.put_bad('not a decodable image')
    assert slot.bad == 1 and slot.newest().seq == 40


def test_decode_returns_pixels_or_raises_value_error():
    image = camera_view.decode(jpeg_of((0, 0, 255), 64, 48))
    assert image.shape == (48, 64, 3) and image[24, 32, 2] > 240 and image[24, 32, 0] < 15
    for data in (b'\xff\xd8 torn', b''):
        with pytest.raises(ValueError, match='not a decodable image'):
            camera_view.decode(data)


def test_the_camera_list_puts_publishing_cameras_first_then_the_known_ones():
    assert camera_view.camera_list(TOPICS, ('room_camera', 'head_camera')) == [
        ('bench', True), ('room_camera', True), ('head_camera', False)]
    assert camera_view.camera_list([], ('room_camera',)) == [('room_camera', False)]


# ---- the pane ---------------------------------------------------------------------------------
class FakeSubscriber:
    def __init__(self, camera):
        self.camera, self.active = camera, True

    def unregister(self):
        self.active = False


class CameraClientDouble(CameraClient):
    """The real CameraClient (slots, decoding, listing) with its subscriber and master faked."""

    def __init__(self, topics=TOPICS):
        self.time_s = 100.0
        super().__init__(clock=lambda: self.time_s)
        self.topics = topics
        self.subscribers = []

    def _subscribe(self, camera, slot):
        self.subscribers.append(FakeSubscriber(camera))
        return self.subscribers[-1]

    def _published_topics(self):
        return self.topics

    def active(self):
        return [s.camera for s in self.subscribers if s.active]

    def publish(self, data, age_s=0.02):
        """Feed the subscription's callback as rospy would, stamped age_s ago."""
        msg = CompressedImage(format='jpeg', data=data)
        msg.header.stamp = rospy.Time.from_sec(self.time_s - age_s)
        self._on_image(msg, (self.camera, self.slot))


def shown_pane(qtbot, client):
    pane = CameraPane(client)
    qtbot.addWidget(pane)
    pane.resize(640, 480)
    pane.show()
    qtbot.waitExposed(pane)
    qtbot.waitUntil(lambda: client.camera_list() is not None)  # the lister thread answered
    pane.refresh()
    return pane


def centre_colour(pane):
    image = pane.view.grab().toImage()
    colour = image.pixelColor(image.width() // 2, image.height() // 2)
    return colour.red(), colour.green(), colour.blue()


def test_the_pane_shows_the_frames_of_the_first_publishing_camera(qtbot):
    client = CameraClientDouble()
    pane = shown_pane(qtbot, client)
    assert client.active() == ['bench']
    assert [pane.chooser.itemText(i) for i in range(pane.chooser.count())][:3] == [
        'bench', 'room_camera', 'head_camera (not publishing)']
    client.publish(jpeg_of((0, 0, 255)))  # red in BGR
    pane.refresh()
    red, green, blue = centre_colour(pane)
    assert red > 220 and green < 40 and blue < 40
    assert '320×240' in pane.status.text() and 'live' in pane.status.text()
    assert GREEN in pane.status.styleSheet()
    client.time_s += 0.05
    client.publish(jpeg_of((255, 0, 0)))  # the next frame, blue
    pane.refresh()
    red, green, blue = centre_colour(pane)
    assert blue > 220 and red < 40
    assert 'age 20 ms' in pane.status.text()


def edge_colour(pane):
    """Return (r, g, b) at the middle of the drawn image's left edge (the alert frame)."""
    image, rect = pane.view.grab().toImage(), pane.view.target_rect()
    colour = image.pixelColor(rect.left() + 2, rect.center().y())
    return colour.red(), colour.green(), colour.blue()


def test_a_stalled_stream_turns_amber_then_red(qtbot):
    client = CameraClientDouble()
    pane = shown_pane(qtbot, client)
    client.publish(jpeg_of((0, 255, 0)))
    pane.refresh()
    assert pane.verdict().level == OK
    assert edge_colour(pane)[1] > 220  # the green image up to its edge: no alert frame
    client.time_s += 0.8
    pane.refresh()
    assert pane.verdict().level == WARN and AMBER in pane.status.styleSheet()
    assert 'stopped' in pane.status.text()
    assert edge_colour(pane) == (0xef, 0x6c, 0x00)  # the image framed in amber
    client.time_s += 2.0
    pane.refresh()
    assert pane.verdict().level == ERROR and RED in pane.status.styleSheet()
    assert edge_colour(pane) == (0xc6, 0x28, 0x28)  # ... then in red
    client.publish(jpeg_of((0, 255, 0)), age_s=1.5)  # arrives, but old
    pane.refresh()
    assert pane.verdict().level == ERROR and 'late' in pane.status.text()


def test_a_corrupt_jpeg_is_counted_and_the_last_good_frame_stays(qtbot):
    client = CameraClientDouble()
    pane = shown_pane(qtbot, client)
    client.publish(jpeg_of((0, 0, 255)))
    client.publish(jpeg_of((255, 0, 0))[:200] + b'garbage')
    client.publish(b'')
    pane.refresh()
    assert '2 undecodable' in pane.status.text()
    assert centre_colour(pane)[0] > 220  # still the red frame


def test_a_hidden_pane_subscribes_to_nothing_and_a_new_camera_replaces_the_old(qtbot):
    client = CameraClientDouble()
    pane = shown_pane(qtbot, client)
    assert client.active() == ['bench']
    pane.hide()
    assert client.active() == [] and not client.subscribed()
    pane.choose('room_camera')  # chosen while hidden: still nothing
    assert client.active() == []
    pane.show()
    qtbot.waitExposed(pane)
    assert client.active() == ['room_camera']
    pane.choose('head_camera')
    assert client.active() == ['head_camera']
    pane.refresh()
    assert not pane.view.has_image() and 'waiting for frames' in pane.status.text()


def test_a_camera_chosen_in_the_chooser_stays_chosen_when_the_list_changes(qtbot):
    client = CameraClientDouble()
    pane = shown_pane(qtbot, client)
    index = pane.chooser.findData('room_camera')
    pane.chooser.activated.emit(index)
    assert client.active() == ['room_camera']
    client.topics = [t for t in TOPICS if not t[0].startswith('/cameras/bench/')]  # bench stops
    client.time_s += 10.0
    pane.refresh()
    qtbot.waitUntil(lambda: ('bench', True) not in client.camera_list())
    pane.refresh()
    assert client.active() == ['room_camera']
    assert pane.chooser.currentData() == 'room_camera'


def test_the_window_subscribes_only_while_the_main_tab_is_shown(qtbot):
    client = CameraClientDouble()
    window = Window(FakeClient(), debug_mode=False, cameras=client)
    qtbot.addWidget(window)
    window.tabs.setCurrentWidget(window.calibration_tab)
    window.show()
    qtbot.waitExposed(window)
    assert client.active() == []  # another tab shows: no subscription
    assert window.tabs.tabText(0) == 'Main' and window.tabs.count() == 2  # no Cameras tab
    window.tabs.setCurrentWidget(window.main_tab)  # the camera is on the main tab
    assert window.tabs.currentWidget() is window.main_tab
    qtbot.waitUntil(lambda: client.camera_list() is not None)
    window.frame()
    assert client.active() == ['bench']  # right_hand_camera does not publish here
    client.publish(jpeg_of((0, 0, 255)))
    window.frame()
    assert window.camera_pane.view.has_image()
    window.tabs.setCurrentWidget(window.calibration_tab)
    assert client.active() == []
    window.frame()  # draws the calibration tab only
