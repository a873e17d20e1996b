"""Helpers for the GUI's rostest scripts: an offscreen Qt application and waiting with Qt."""
import os

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

from PyQt5 import QtWidgets  # noqa: E402

import robopuppet.gui  # noqa: E402,F401  (selects PyQt5 for pyqtgraph)
from waiting import wait_for  # noqa: E402


_APP = []  # keeps the QApplication alive for the whole process


def application():
    """Return the process's QApplication, creating it once."""
    if not _APP:
        _APP.append(QtWidgets.QApplication.instance() or QtWidgets.QApplication(['rostest']))
    return _APP[0]


def wait_until(predicate, timeout_s, step_s=0.02):
    """Process Qt events until predicate() is true; return its last value."""
    app = application()

    def pumped():
        app.processEvents()
        return predicate()
    return wait_for(pumped, timeout_s, step_s=step_s)


def wait_for_subscribers(publishers, timeout_s=10.0):
    """Wait until every publisher has at least one subscriber; return whether they all do."""
    return wait_until(lambda: all(p.get_num_connections() > 0 for p in publishers), timeout_s)
