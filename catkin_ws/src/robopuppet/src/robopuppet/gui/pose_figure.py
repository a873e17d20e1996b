"""A drawing of a pose: one dial per joint, the target needle beside the puppet's reading."""
import math

from PyQt5 import QtCore, QtGui, QtWidgets

from robopuppet import settings

# Baxter's names of the seven joints, in order (shoulder, elbow, wrist).
JOINT_LABELS = ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')
TARGET_COLOUR, READING_COLOUR = QtGui.QColor('#1565c0'), QtGui.QColor('#ef6c00')


class PoseFigure(QtWidgets.QWidget):
    """Seven dials: 0 rad points up and positive angles turn counter-clockwise (REP 103).

    The blue needle is the pose to take, the orange one what the puppet reports; show() sets
    both (rad, NaN or None for none).
    """

    def __init__(self, parent=None):
        super().__init__(parent)
        self.targets_rad = [math.nan] * settings.NUM_JOINTS
        self.readings_rad = [math.nan] * settings.NUM_JOINTS
        self.setMinimumSize(7 * 90, 150)

    def show_pose(self, targets_rad, readings_rad):
        """Draw these target and reported angles (rad) at the next paint."""
        self.targets_rad = [math.nan if a is None else a for a in targets_rad]
        self.readings_rad = [math.nan if a is None else a for a in readings_rad]
        self.update()

    def paintEvent(self, event):  # noqa: N802 (Qt's name)
        painter = QtGui.QPainter(self)
        painter.setRenderHint(QtGui.QPainter.Antialiasing)
        cell = self.width() / settings.NUM_JOINTS
        radius = max(10.0, min(cell * 0.4, (self.height() - 50) / 2.0))
        for joint in settings.JOINTS:
            centre = QtCore.QPointF(cell * (joint + 0.5), 12 + radius)
            painter.setPen(QtGui.QPen(QtCore.Qt.gray, 1))
            painter.setBrush(QtGui.QColor('#fafafa'))
            painter.drawEllipse(centre, radius, radius)
            top = centre - QtCore.QPointF(0, radius)
            painter.drawLine(top, top + QtCore.QPointF(0, radius * 0.2))  # the 0 rad mark
            for angle, colour, width in ((self.readings_rad[joint], READING_COLOUR, 3),
                                         (self.targets_rad[joint], TARGET_COLOUR, 4)):
                if math.isfinite(angle):
                    tip = centre + QtCore.QPointF(-math.sin(angle), -math.cos(angle)) * radius
                    painter.setPen(QtGui.QPen(colour, width, QtCore.Qt.SolidLine,
                                              QtCore.Qt.RoundCap))
                    painter.drawLine(centre, tip)
            painter.setPen(QtCore.Qt.black)
            text = 'joint %d (%s)\n%s' % (joint, JOINT_LABELS[joint],
                                          _number(self.targets_rad[joint]))
            painter.drawText(QtCore.QRectF(cell * joint, 16 + 2 * radius, cell, 34),
                             QtCore.Qt.AlignHCenter | QtCore.Qt.AlignTop, text)
        painter.end()


def _number(angle_rad):
    return '—' if not math.isfinite(angle_rad) else '%+.2f rad' % angle_rad
