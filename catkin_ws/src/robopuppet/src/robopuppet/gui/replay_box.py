"""The replay control (in the Recording box): play a recorded episode onto Baxter or into this
window's puppet, stop it, and show the episode's plot (in a gui.plot_dialog window).

It runs the real commands as child processes (QProcess: their output is read as it arrives,
the GUI thread never waits on them): `rosrun robopuppet replay` and, for a missing plot,
`rosrun robopuppet export --plot`. Stop publishes std_msgs/Empty on interface.REPLAY_STOP
(through the client); a replay that has not ended STOP_GRACE_S later is terminated, then
killed. Closing the window stops a running replay the same way.
"""
import os

from PyQt5 import QtCore, QtWidgets

from robopuppet.episodes import replay_control as rc
from robopuppet.gui.plot_dialog import PlotDialog

STOP_GRACE_S = 5.0     # after Stop: then SIGTERM, and as long again: SIGKILL
CLOSE_WAIT_S = 3.0     # closing the window waits this long for the replay to stop itself
MIN_SPEED, MAX_SPEED = 0.1, 2.0


class ReplayBox(QtWidgets.QWidget):
    """Episode list (newest first), onto Baxter / into the puppet, speed, Play, Stop, Plot.

    Args:
        client: a PuppetClient (or a test double) with .side, recording_status(),
            episodes_dir() and stop_replay().
        replay_command, export_command: the commands run (programs and leading arguments).
        open_file(path): shows a plot (default: show_plot, a PlotDialog in the GUI).
    """

    def __init__(self, client, replay_command=rc.REPLAY_COMMAND,
                 export_command=rc.EXPORT_COMMAND, open_file=None, parent=None):
        super().__init__(parent)
        self._client, self._open_file = client, open_file or self.show_plot
        self.plot_dialog = None        # the PlotDialog shown last
        self._commands = {'replay': replay_command, 'export': export_command}
        self.process = self.exporter = None
        self._terminated = False
        self.arguments = None          # the running replay's arguments
        self._state, self._partial, self._listed, self._filtered = '', '', None, None
        self.episodes = QtWidgets.QComboBox()
        self.episodes.setMinimumContentsLength(28)
        self.rescan_button = QtWidgets.QToolButton(text='↻', toolTip='list the episodes again')
        self.rescan_button.clicked.connect(self.rescan)
        self.target = QtWidgets.QComboBox()
        self.target.addItem('onto Baxter', rc.ONTO_ROBOT)
        self.target.addItem('into puppet %s' % client.side, rc.INTO_PUPPET)
        self.speed = QtWidgets.QDoubleSpinBox(minimum=MIN_SPEED, maximum=MAX_SPEED,
                                              singleStep=0.1, value=1.0, suffix=' x')
        self.play_button = QtWidgets.QPushButton('Play')
        self.play_button.clicked.connect(self.play)
        self.stop_button = QtWidgets.QPushButton('Stop')
        self.stop_button.clicked.connect(self.stop)
        self.plot_button = QtWidgets.QPushButton('Plot')
        self.plot_button.clicked.connect(self.plot)
        self.state_label = QtWidgets.QLabel('no replay yet')
        # One line that never widens the window: a long state is cut, the tooltip holds it all.
        self.state_label.setSizePolicy(QtWidgets.QSizePolicy.Ignored,
                                       QtWidgets.QSizePolicy.Preferred)
        self._escalate = QtCore.QTimer(self, singleShot=True, timeout=self._escalate_stop)
        row = QtWidgets.QHBoxLayout()
        row.setContentsMargins(0, 0, 0, 0)
        for widget, stretch in ((QtWidgets.QLabel('Replay'), 0), (self.episodes, 1),
                                (self.rescan_button, 0), (self.target, 0), (self.speed, 0),
                                (self.play_button, 0), (self.stop_button, 0),
                                (self.plot_button, 0)):
            row.addWidget(widget, stretch)
        rows = QtWidgets.QVBoxLayout(self)
        rows.setContentsMargins(0, 0, 0, 0)
        rows.setSpacing(2)
        rows.addLayout(row)
        rows.addWidget(self.state_label)
        QtWidgets.QApplication.instance().aboutToQuit.connect(self.stop_now)
        self._enable()

    # ---- the episode list ------------------------------------------------------------------

    def directory(self):
        """Return the episodes directory: the recorder's (from its last episode), else the
        default one."""
        status = self._client.recording_status()
        if status is not None and status.episode:
            return os.path.dirname(status.episode)
        return self._client.episodes_dir()

    def rescan(self):
        """List the episodes again, newest first, keeping the one chosen if it is still there."""
        chosen = self.episode()
        directory = self.directory()
        listed = rc.list_episodes(directory)
        self.episodes.clear()
        for episode in listed:
            self.episodes.addItem(rc.label(episode), episode)
        if not listed:
            self.episodes.addItem('no episodes in %s' % directory, None)
        bags = [e.bag for e in listed]
        if chosen is not None and chosen.bag in bags:
            self.episodes.setCurrentIndex(bags.index(chosen.bag))
        self._enable()

    def episode(self):
        """Return the chosen replay_control.Episode, or None."""
        return self.episodes.currentData()

    # ---- replay ----------------------------------------------------------------------------

    def running(self):
        """Return True while a replay runs."""
        return self.process is not None

    def play(self):
        """Start the replay command on the chosen episode."""
        episode = self.episode()
        if episode is None or self.running():
            return
        self.arguments = rc.replay_arguments(episode, self.target.currentData(),
                                             self._client.side, self.speed.value())
        self._terminated = False
        self.process = self._start('replay', self.arguments, self._replay_ended)
        self.process.readyReadStandardOutput.connect(self._read)
        self._show('starting: %s' % episode.name)

    def stop(self):
        """Ask the running replay to stop (REPLAY_STOP); terminate it if it does not."""
        if not self.running():
            return
        self._client.stop_replay()
        self._show('stopping')
        self._escalate.start(int(STOP_GRACE_S * 1000))

    def stop_now(self):
        """Stop a running replay before the window goes: ask, wait a little, then end it."""
        process = self.process
        if process is None:
            return
        try:
            self._client.stop_replay()
        except Exception:  # pylint: disable=broad-except  (ROS may be down already)
            pass
        for end in (None, process.terminate, process.kill):
            if end is not None:
                end()
            if process.waitForFinished(int(CLOSE_WAIT_S * 1000)):
                break

    def _escalate_stop(self):
        """SIGTERM a replay still running STOP_GRACE_S after Stop, SIGKILL it as long after."""
        if self.process is None or self.process.state() == QtCore.QProcess.NotRunning:
            return
        if self._terminated:
            self.process.kill()
            return
        self._terminated = True
        if not rc.has_ended(self._state):  # else it said how it ended and is only slow to exit
            self._show('terminating: it did not stop within %g s' % STOP_GRACE_S)
        self.process.terminate()
        self._escalate.start(int(STOP_GRACE_S * 1000))

    def _read(self):
        if self.process is None:
            return
        text = self._partial + bytes(self.process.readAllStandardOutput()).decode(
            errors='replace')
        lines = text.split('\n')
        self._partial = lines.pop()
        for line in lines:
            state = rc.state_from_line(line)
            if state is not None:
                self._show(state)

    def _replay_ended(self, code, status):
        self._read()
        if self._partial:
            self._partial += '\n'
            self._read()
        self._escalate.stop()
        self.process.deleteLater()
        self.process = None
        normal = status == QtCore.QProcess.NormalExit
        self._show(rc.exit_text(code if normal else None, self._state))

    # ---- plot ------------------------------------------------------------------------------

    def plot(self):
        """Open the chosen episode's plot; make it first (export --plot) if it is missing."""
        episode = self.episode()
        if episode is None or self.exporter is not None:
            return
        path = rc.plot_path(episode)
        if os.path.exists(path):
            self._open_file(path)
            return
        self.exporter = self._start('export', rc.export_arguments(episode),
                                    lambda code, status: self._plot_made(code, status, path))
        self.plot_button.setText('making the plot…')
        self._enable()

    def show_plot(self, path):
        """Show the plot in a PlotDialog (one at a time: a new plot replaces the last)."""
        try:
            dialog = PlotDialog(path, self)
        except OSError as error:
            self._show('no plot: %s' % error)
            return
        if self.plot_dialog is not None:
            self.plot_dialog.close()
        self.plot_dialog = dialog
        dialog.show()
        dialog.raise_()

    def _plot_made(self, code, status, path):
        output = bytes(self.exporter.readAllStandardOutput()).decode(errors='replace')
        self.exporter.deleteLater()
        self.exporter = None
        self.plot_button.setText('Plot')
        if status == QtCore.QProcess.NormalExit and code == 0 and os.path.exists(path):
            self._open_file(path)
        else:
            lines = [line for line in output.splitlines() if line.strip()]
            errors = [line for line in lines if ': error: ' in line] or lines
            self._show('no plot: %s' % (errors[-1] if errors else 'export failed'))
        self._enable()

    # ---- helpers ---------------------------------------------------------------------------

    def _start(self, which, arguments, ended):
        program, *leading = self._commands[which]
        process = QtCore.QProcess(self)
        process.setProcessChannelMode(QtCore.QProcess.MergedChannels)
        process.finished.connect(ended)
        process.errorOccurred.connect(lambda error: self._failed_to_start(process, which, error))
        process.start(program, list(leading) + list(arguments))
        return process

    def _failed_to_start(self, process, which, error):
        if error == QtCore.QProcess.FailedToStart:
            self._show('cannot start %s: %s' % (which, process.errorString()))
            if process is self.process:
                self.process = None
            if process is self.exporter:
                self.exporter = None
                self.plot_button.setText('Plot')
            process.deleteLater()
            self._enable()

    def _show(self, state):
        self._state = state
        self.state_label.setText(state)
        self.state_label.setToolTip(state)
        self._enable()

    def _enable(self):
        chosen = self.episode() is not None
        running = self.running()
        self.play_button.setEnabled(chosen and not running)
        self.stop_button.setEnabled(running)
        self.plot_button.setEnabled(chosen and self.exporter is None)
        for widget in (self.episodes, self.rescan_button, self.target, self.speed):
            widget.setEnabled(not running)

    def refresh(self):
        """List the episodes again when the recorder's status changed (call once per frame)."""
        status = self._client.recording_status()
        seen = (self.directory(), None if status is None else (status.recording, status.episode))
        if seen != self._listed:
            self._listed = seen
            self.rescan()

    def showEvent(self, event):  # noqa: N802  (Qt's name)
        """Watch the window this box is in: closing it stops a running replay."""
        if self._filtered is None:
            self._filtered = self.window()
            self._filtered.installEventFilter(self)
        super().showEvent(event)

    def eventFilter(self, watched, event):  # noqa: N802  (Qt's name)
        """Stop a running replay when the window closes (the close goes on)."""
        if watched is self._filtered and event.type() == QtCore.QEvent.Close:
            self.stop_now()
        return False
