"""The camera pane, beside the main tab: one camera's images, frames/s and age, coloured by health.

The pane subscribes only while it is visible (CameraClient); the ROS thread decodes, and
refresh() (the window's frame timer, GUI thread) draws the newest frame when there is a new one.
"""
import collections

import cv2
from PyQt5 import QtCore, QtGui, QtWidgets

from robopuppet.gui import camera_view
from robopuppet.gui.look import AMBER, GREEN, RED, paint

LEVEL_COLOUR = {camera_view.OK: GREEN, camera_view.WARN: AMBER, camera_view.ERROR: RED}
# A stale image gets a frame and a banner in a strong colour: the nurse looks at the image.
ALERT_COLOUR = {camera_view.WARN: QtGui.QColor('#ef6c00'),
                camera_view.ERROR: QtGui.QColor('#c62828')}
ALERT_WIDTH = 6  # pixels
LIST_PERIOD_S = 5.0  # while visible, the chooser asks the master for cameras this often
BACKGROUND = QtGui.QColor('#202020')


class ImageView(QtWidgets.QWidget):
    """Draw a BGR numpy image scaled to fit (aspect kept), centred on a dark background.

    Scaling happens once per new image (cv2.resize, fast) rather than in every paint.
    """

    def __init__(self, clock, parent=None):
        super().__init__(parent)
        self._clock = clock
        self.setSizePolicy(QtWidgets.QSizePolicy.Expanding, QtWidgets.QSizePolicy.Expanding)
        self.setMinimumSize(160, 120)
        self.setAttribute(QtCore.Qt.WA_OpaquePaintEvent)
        self._image = None  # the numpy image as received
        self._scaled = None  # (numpy image at the drawn size, its QImage)
        self._stamp_s = None  # the new image's stamp until it is first drawn
        self.placeholder = 'no image'
        self._alert = None  # (level, text) drawn over a stale image, or None
        self.display_ages_s = collections.deque(maxlen=1000)

    def set_image(self, image, stamp_s=None):
        """Show a new BGR numpy image (or None for the placeholder text) stamped stamp_s."""
        self._image, self._scaled, self._stamp_s = image, None, stamp_s
        self.update()

    def has_image(self):
        return self._image is not None

    def set_placeholder(self, text):
        """Say `text` where the image goes while there is none."""
        if text != self.placeholder:
            self.placeholder = text
            if self._image is None:
                self.update()

    def set_alert(self, level, text):
        """Frame the image and show `text` on it in the level's colour (none when OK)."""
        alert = None if level == camera_view.OK else (level, text)
        if alert != self._alert:
            self._alert = alert
            self.update()

    def target_rect(self):
        """Return the QRect the image is drawn in: the widget, less bars on two sides."""
        if self._image is None:
            return QtCore.QRect()
        height, width = self._image.shape[:2]
        scale = min(self.width() / width, self.height() / height)
        w, h = max(int(width * scale), 1), max(int(height * scale), 1)
        return QtCore.QRect((self.width() - w) // 2, (self.height() - h) // 2, w, h)

    def resizeEvent(self, event):
        self._scaled = None
        super().resizeEvent(event)

    def paintEvent(self, event):
        painter = QtGui.QPainter(self)
        painter.fillRect(self.rect(), BACKGROUND)
        if self._image is None:
            painter.setPen(QtGui.QColor('#c0c0c0'))
            painter.drawText(self.rect(), QtCore.Qt.AlignCenter, self.placeholder)
        else:
            rect = self.target_rect()
            if self._scaled is None or self._scaled[0].shape[:2] != (rect.height(), rect.width()):
                scaled = self._image
                if scaled.shape[:2] != (rect.height(), rect.width()):
                    # INTER_AREA only where it matters (half size or less): it costs ~8 times
                    # INTER_LINEAR at a slight shrink (5 ms for 640x480).
                    halved = 2 * rect.width() <= scaled.shape[1]
                    scaled = cv2.resize(scaled, (rect.width(), rect.height()), interpolation=(
                        cv2.INTER_AREA if halved else cv2.INTER_LINEAR))
                # QImage shares the array's memory: keep the array alive beside it.
                qimage = QtGui.QImage(scaled.data, scaled.shape[1], scaled.shape[0],
                                      scaled.strides[0], QtGui.QImage.Format_BGR888)
                self._scaled = (scaled, qimage)
            painter.drawImage(rect.topLeft(), self._scaled[1])
            if self._alert is not None:
                self._draw_alert(painter, rect, *self._alert)
        painter.end()
        if self._stamp_s is not None:  # publish-to-display age of a new image
            self.display_ages_s.append(self._clock() - self._stamp_s)
            self._stamp_s = None


    @staticmethod
    def _draw_alert(painter, rect, level, text):
        colour = ALERT_COLOUR[level]
        painter.setPen(QtGui.QPen(colour, ALERT_WIDTH, join=QtCore.Qt.MiterJoin))
        inset = ALERT_WIDTH // 2
        painter.drawRect(rect.adjusted(inset, inset, -inset, -inset))
        metrics = painter.fontMetrics()
        banner = QtCore.QRect(rect.left(), rect.top(), rect.width(), metrics.height() + 8)
        painter.fillRect(banner, colour)
        painter.setPen(QtGui.QColor('white'))
        painter.drawText(banner.adjusted(8, 0, -8, 0), QtCore.Qt.AlignVCenter, text)


class CameraPane(QtWidgets.QWidget):
    """Choose a camera and watch it; the status line gives size, frames/s, age and health.

    Args:
        client: a CameraClient (or a test double with now(), subscribe(), unsubscribe(),
            subscribed(), slot, subscribed_s, request_camera_list() and camera_list()).
    Attributes:
        view.display_ages_s: the age (now minus stamp, s) of each frame when it was first
            drawn, the newest 1000 (for the benchmark).
    """

    def __init__(self, client, parent=None):
        super().__init__(parent)
        self.client = client
        self.camera = None  # the chosen camera's name
        self.preferred = None  # the camera shown until the operator chooses one (prefer())
        self.chosen_by_operator = False
        self._listed = None
        self._listed_s = None
        self._shown_seq = None
        self.chooser = QtWidgets.QComboBox()
        self.chooser.setSizeAdjustPolicy(QtWidgets.QComboBox.AdjustToContents)
        self.chooser.setToolTip('the cameras publishing on /cameras/NAME/image/compressed, '
                                'then the known names not publishing yet')
        self.chooser.activated.connect(lambda index: self.choose(self.chooser.itemData(index)))
        self.status = QtWidgets.QLabel('—')
        self.status.setSizePolicy(QtWidgets.QSizePolicy.Ignored,
                                  QtWidgets.QSizePolicy.Preferred)  # long text: no wider window
        self.view = ImageView(client.now)
        top = QtWidgets.QHBoxLayout()
        top.addWidget(QtWidgets.QLabel('Camera:'))
        top.addWidget(self.chooser)
        top.addWidget(self.status, 1)
        layout = QtWidgets.QVBoxLayout(self)
        layout.addLayout(top)
        layout.addWidget(self.view, 1)

    def choose(self, camera, by_operator=True):
        """Show `camera` (a name) from now on; subscribe to it if the pane is visible.

        A camera the operator chose (by_operator) stays: prefer() no longer changes it.
        """
        if camera is None:
            return
        self.chosen_by_operator = self.chosen_by_operator or by_operator
        if camera != self.camera:
            self.camera, self._shown_seq = camera, None
            self.view.set_image(None)
            self.client.unsubscribe()
            self.view.display_ages_s.clear()
            self._fill_chooser()
        if self.isVisible() and not self.client.subscribed():
            self.client.subscribe(camera)

    def prefer(self, camera):
        """Show `camera` (the arm's own) when it publishes, unless the operator chose one."""
        self.preferred = camera
        if (not self.chosen_by_operator and camera != self.camera
                and (camera, True) in (self._listed or [])):
            self.choose(camera, by_operator=False)

    def showEvent(self, event):
        super().showEvent(event)
        self._listed_s = self.client.now()  # ask the master again at once
        self.client.request_camera_list()
        if self.camera is not None and not self.client.subscribed():
            self._shown_seq = None
            self.view.set_image(None)  # not an old frame as if it were live: wait for a new one
            self.client.subscribe(self.camera)

    def hideEvent(self, event):
        super().hideEvent(event)
        self.client.unsubscribe()  # a hidden pane receives and decodes nothing

    def refresh(self, snapshot=None, now_s=None):
        """Draw the newest frame if it is new, and the status line (GUI thread, per frame).

        The arguments are the window's (ArmState snapshot and its time) and are not used: the
        age is taken on the camera client's clock, the time base of the stamps.
        """
        now_s = self.client.now()
        self._update_list(now_s)
        slot = self.client.slot if self.client.subscribed() else None
        frame = slot.newest() if slot is not None else None
        if frame is not None and frame.seq != self._shown_seq:
            self._shown_seq = frame.seq
            self.view.set_image(frame.image, frame.stamp_s)
        verdict = camera_view.judge(now_s, frame, self.client.subscribed_s)
        parts = [self.camera or 'no camera']
        if frame is not None:
            height, width = frame.image.shape[:2]
            parts += ['%d×%d' % (width, height),
                      '%.1f frames/s' % slot.rate_hz(now_s, self.client.subscribed_s),
                      'age %s' % camera_view.duration(max(now_s - frame.stamp_s, 0.0))]
        if slot is not None and slot.bad:
            parts.append('%d undecodable' % slot.bad)
        self.status.setText('%s — %s' % ('   '.join(parts), verdict.text))
        self.status.setToolTip(slot.last_problem if slot is not None and slot.bad else '')
        paint(self.status, LEVEL_COLOUR[verdict.level])
        self.view.set_alert(verdict.level, verdict.text)
        if frame is None:
            self.view.set_placeholder(verdict.text)

    def verdict(self):
        """Return the camera_view.Verdict shown now (for tests)."""
        slot = self.client.slot if self.client.subscribed() else None
        return camera_view.judge(self.client.now(), slot.newest() if slot else None,
                                 self.client.subscribed_s)

    def _update_list(self, now_s):
        if self._listed_s is None or now_s - self._listed_s >= LIST_PERIOD_S:
            self._listed_s = now_s
            self.client.request_camera_list()
        cameras = self.client.camera_list()
        if cameras is None or cameras == self._listed:
            return
        self._listed = cameras
        live = [name for name, published in cameras if published]
        if self.camera is None and live:  # until the operator chooses: preferred or first live
            self.choose(self.preferred if self.preferred in live else live[0], False)
        elif self.preferred in live:
            self.prefer(self.preferred)
        self._fill_chooser()

    def _fill_chooser(self):
        cameras = list(self._listed or [])
        if self.camera is not None and self.camera not in [name for name, _ in cameras]:
            cameras.insert(0, (self.camera, False))
        self.chooser.blockSignals(True)
        self.chooser.clear()
        for name, published in cameras:
            self.chooser.addItem(name if published else '%s (not publishing)' % name, name)
        self.chooser.setCurrentIndex(max(self.chooser.findData(self.camera), 0)
                                     if self.camera is not None else -1)
        self.chooser.blockSignals(False)
