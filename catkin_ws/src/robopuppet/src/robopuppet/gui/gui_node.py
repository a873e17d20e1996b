"""gui_X: the calibration and tuning window of one puppet arm."""
import sys

import rospy
from PyQt5 import QtCore, QtWidgets

from robopuppet import interface
from robopuppet.gui.camera_client import CameraClient
from robopuppet.gui.puppet_client import PuppetClient, SimPuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.study_topics import StudyTopics
from robopuppet.gui.window import Window
from robopuppet.link_recovery import LinkRecovery
from robopuppet.periodic import Guard

DEFAULT_FRAME_RATE_HZ = 30.0


class ShutdownBridge(QtCore.QObject):
    """Carry rospy's shutdown (on any thread) to the GUI thread as a queued Qt signal."""

    shutdown = QtCore.pyqtSignal()


def read_params():
    """Return (side, frame_rate_hz, debug_mode, sim_puppet) from the private parameters.

    Raises:
        KeyError: ~arm_side is missing.
        ValueError: ~arm_side is not L or R, or ~frame_rate is not a positive number.
    """
    side = rospy.get_param('~arm_side')
    interface.check_side(side)
    frame_rate_hz = rospy.get_param('~frame_rate', DEFAULT_FRAME_RATE_HZ)
    if not isinstance(frame_rate_hz, (int, float)) or not 0 < frame_rate_hz <= 1000:
        raise ValueError('~frame_rate must be a number of Hz in (0, 1000], got %r'
                         % (frame_rate_hz,))
    return (side, float(frame_rate_hz), bool(rospy.get_param('~debug_mode', True)),
            bool(rospy.get_param('~sim_puppet', False)))


def main():
    """Run the GUI node until its window closes or ROS shuts down.

    Node gui_X (see Window, PuppetClient and SimPuppetClient for the topics):
    Subscribes: /puppet/arm_X/{heartbeat, opmode, teleop_state, user_btn, gripper_G,
        joint_J/enc_stat, joint_J/angle, joint_J/voltage, joint_J/setpoint, link_state},
        /diagnostics; /robot/joint_states from the robot host (queue 1: the newest sample
        only, for the tracking error); while the Cameras tab shows, the chosen camera's
        /cameras/<name>/image/compressed (see CameraClient).
    Publishes: /puppet/arm_X/opmode, /puppet/arm_X/joint_J/setpoint; with ~sim_puppet also
        /puppet_sim/arm_X/{hand, button, grippers} (latched).
    Calls: /puppet/arm_X/get_config (Get), /puppet/arm_X/set_config (Set).
    Parameters:
        ~arm_side (str, required): 'L' or 'R'.
        ~frame_rate (float, default 30 Hz): redraws per second of the visible tab.
        ~debug_mode (bool, default true): show the seven joint tabs.
        ~sim_puppet (bool, default false): show the virtual puppet panel.
        ~study (bool, default false): show the study tab (see StudyTopics: subscribes
            /puppet/study/state, publishes /puppet/study/questionnaire, calls
            /puppet/study/start).
    """
    rospy.init_node('gui')
    try:
        side, frame_rate_hz, debug_mode, sim_puppet = read_params()
    except (KeyError, ValueError) as error:
        rospy.logfatal('gui cannot start: %s', error)
        raise SystemExit(1)
    # After a cut: connect anew to the robot host's publishers once these are stuck.
    LinkRecovery(rospy.get_name(), ['%s/%s' % (interface.puppet_ns(side), interface.LINK_STATE),
                                    interface.ROBOT_JOINT_STATES]).start()
    study = bool(rospy.get_param('~study', False))
    app = QtWidgets.QApplication(sys.argv[:1])
    window = Window(PuppetClient(side, ArmState()), debug_mode,
                    SimPuppetClient(side) if sim_puppet else None, CameraClient(),
                    StudyTopics() if study else None)
    rospy.loginfo('gui for arm %s: %.0f frames/s, joint tabs %s, virtual puppet %s, study tab '
                  '%s', side, frame_rate_hz, 'on' if debug_mode else 'off',
                  'on' if sim_puppet else 'off', 'on' if study else 'off')
    run(app, window, frame_rate_hz)


def run(app, window, frame_rate_hz):
    """Show the window and draw frames until it closes or ROS shuts down; then end ROS too."""
    bridge = ShutdownBridge()
    bridge.shutdown.connect(window.close, QtCore.Qt.QueuedConnection)
    rospy.on_shutdown(bridge.shutdown.emit)
    timer = QtCore.QTimer()
    guard = Guard(rospy.get_name(), rospy.logerr)  # a failing frame must not end the GUI
    timer.timeout.connect(lambda: guard.call('frame', window.frame))
    # The timer also hands control to Python regularly, so rospy's Ctrl-C handler runs.
    timer.start(int(round(1000.0 / frame_rate_hz)))
    if not rospy.is_shutdown():
        window.show()
        app.exec_()
    timer.stop()
    rospy.signal_shutdown('window closed')
