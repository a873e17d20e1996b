"""Config node calls off the GUI thread: a blocking call on a worker thread, its answer back on
the GUI thread through a queued Qt signal, and a deadline kept by the GUI thread."""
import threading

from PyQt5 import QtCore

from robopuppet.gui.puppet_client import ConfigUnavailable


class ConfigTask(QtCore.QObject):
    """Run one blocking config node call at a time so that the window keeps drawing meanwhile.

    start(work, on_done, timeout_s) runs work() on a new daemon thread. Its result, or the
    ConfigUnavailable it raises, comes back through a queued signal and on_done(result, error
    text or None) runs on the GUI thread. When no answer came within timeout_s, on_done(None,
    'no answer within N s') runs instead and the late answer is dropped: a call that hangs holds
    only its own thread.
    """

    _answered = QtCore.pyqtSignal(int, object, object)  # ticket, result, error text

    def __init__(self, parent=None):
        super().__init__(parent)
        self._ticket = 0
        self._on_done = None
        self._timeout_s = 0.0
        self._timer = QtCore.QTimer(self)
        self._timer.setSingleShot(True)
        self._timer.timeout.connect(self._expire)
        self._answered.connect(self._finish, QtCore.Qt.QueuedConnection)

    def busy(self):
        """Return True while a job has neither answered nor timed out."""
        return self._on_done is not None

    def start(self, work, on_done, timeout_s):
        """Run work() off the GUI thread; on_done(result, error) later on the GUI thread.

        Raises:
            RuntimeError: a job is still running (wait until busy() is False).
        """
        if self.busy():
            raise RuntimeError('a config node call is still running')
        self._ticket += 1
        self._on_done = on_done
        self._timeout_s = timeout_s
        threading.Thread(target=self._run, args=(self._ticket, work), name='config call',
                         daemon=True).start()
        self._timer.start(int(round(timeout_s * 1000)))

    def _run(self, ticket, work):
        try:
            result, error = work(), None
        except ConfigUnavailable as unavailable:
            result, error = None, str(unavailable)
        try:
            self._answered.emit(ticket, result, error)
        except RuntimeError:  # the window was closed meanwhile: nobody waits for the answer
            pass

    def _finish(self, ticket, result, error):
        if ticket == self._ticket and self.busy():
            self._end(result, error)

    def _expire(self):
        if self.busy():
            self._end(None, 'no answer within %g s' % self._timeout_s)

    def _end(self, result, error):
        on_done, self._on_done = self._on_done, None
        self._timer.stop()
        on_done(result, error)

