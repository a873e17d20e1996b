"""A window that shows an episode's plot (a PNG) in the GUI, scrollable at full size.

The GUI shows the plot itself, so no desktop image viewer is needed; "Open in the image
viewer" hands the file to the desktop's viewer when there is one.
"""
import os

from PyQt5 import QtCore, QtGui, QtWidgets

MAX_START_SIZE = (1200, 800)  # pixels: the dialog opens at most this large; the image scrolls
MAX_PATH_PIXELS = 700  # the file's path beside the buttons, elided beyond this


class PlotDialog(QtWidgets.QDialog):
    """Show the PNG at `path` (QtGui.QPixmap) in a scroll area, with Close and Open buttons.

    Raises:
        OSError: the file is not an image Qt can read.
    """

    def __init__(self, path, parent=None):
        super().__init__(parent)
        self.path = path
        self.pixmap = QtGui.QPixmap(path)
        if self.pixmap.isNull():
            raise OSError('cannot read the plot %s' % path)
        self.setWindowTitle('Plot: %s' % os.path.basename(path))
        self.image = QtWidgets.QLabel()
        self.image.setPixmap(self.pixmap)
        self.scroll = QtWidgets.QScrollArea()
        self.scroll.setWidget(self.image)
        self.scroll.setAlignment(QtCore.Qt.AlignCenter)
        viewer = QtWidgets.QPushButton('Open in the image viewer')
        viewer.setToolTip(path)
        viewer.clicked.connect(lambda: QtGui.QDesktopServices.openUrl(
            QtCore.QUrl.fromLocalFile(path)))
        close = QtWidgets.QPushButton('Close')
        close.clicked.connect(self.close)
        row = QtWidgets.QHBoxLayout()
        shown = QtWidgets.QLabel()   # a long path is cut in the middle, not a wider window
        shown.setToolTip(path)
        shown.setText(shown.fontMetrics().elidedText(path, QtCore.Qt.ElideMiddle,
                                                      MAX_PATH_PIXELS))
        row.addWidget(shown, 1)
        row.addWidget(viewer)
        row.addWidget(close)
        layout = QtWidgets.QVBoxLayout(self)
        layout.addWidget(self.scroll, 1)
        layout.addLayout(row)
        frame = 2 * self.scroll.frameWidth() + 40
        self.resize(min(self.pixmap.width() + frame, MAX_START_SIZE[0]),
                    min(self.pixmap.height() + frame + 40, MAX_START_SIZE[1]))
