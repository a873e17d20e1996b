"""The GUI window: main tab (with the camera beside the status), calibration wizard, optional
study tab, joint tabs and virtual puppet panel."""
from PyQt5 import QtWidgets

from robopuppet import settings
from robopuppet.gui.calibration_tab import CalibrationTab
from robopuppet.gui.camera_pane import CameraPane
from robopuppet.gui.joint_tab import JointTab
from robopuppet.gui.main_tab import MainTab
from robopuppet.gui.sim_panel import SimPanel
from robopuppet.gui.study_tab import StudyTab

DEFAULT_SIZE = (1280, 760)  # pixels; the benchmark measures the frame rate at this size
PLOT_WINDOW_S = 10.0


class Window(QtWidgets.QMainWindow):
    """One arm's window. `frame()` drains the ArmState and redraws the visible tab only.

    Args:
        client: a PuppetClient (or a test double with .side, .state, .now() and its setters).
        debug_mode: show the seven joint tabs.
        sim: a SimPuppetClient to show the virtual puppet panel, or None.
        cameras: a CameraClient to show the camera pane on the main tab, beside the status
            (camera_pane), or None.
        study: a StudyTopics to show the study tab (shown first), or None.
    """

    def __init__(self, client, debug_mode=True, sim=None, cameras=None, study=None):
        super().__init__()
        self.client = client
        self.setWindowTitle('RoboPuppet — arm %s' % client.side)
        self.tabs = QtWidgets.QTabWidget()
        self.camera_pane = CameraPane(cameras) if cameras is not None else None
        self.main_tab = MainTab(client, self.camera_pane)
        self.tabs.addTab(self.main_tab, 'Main')
        self.calibration_tab = CalibrationTab(client)
        self.tabs.addTab(self.calibration_tab, 'Calibration')
        self.study_tab = StudyTab(study) if study is not None else None
        if self.study_tab is not None:
            self.tabs.insertTab(1, self.study_tab, 'Study')
            self.tabs.setCurrentWidget(self.study_tab)
        self.joint_tabs = []
        if debug_mode:
            for joint in settings.JOINTS:
                tab = JointTab(client, joint, PLOT_WINDOW_S)
                self.tabs.addTab(tab, 'Joint %d' % joint)
                self.joint_tabs.append(tab)
        self.sim = sim
        self.sim_panel = SimPanel(sim) if sim is not None else None
        if self.sim_panel is None:
            self.setCentralWidget(self.tabs)
        else:
            splitter = QtWidgets.QSplitter()
            splitter.addWidget(self.tabs)
            splitter.addWidget(self.sim_panel)
            splitter.setStretchFactor(0, 1)
            self.setCentralWidget(splitter)
        self.frames = 0
        self.resize(*DEFAULT_SIZE)

    def frame(self):
        """Take in what arrived since the last frame and redraw the tab on screen."""
        now_s = self.client.now()
        points = self.client.state.drain()
        for tab in self.joint_tabs:
            tab.extend(points)
        current = self.tabs.currentWidget()
        current.refresh(self.client.state.snapshot(), now_s)
        if self.study_tab is not None and current is not self.study_tab:
            self.study_tab.watch(now_s)   # the questionnaire opens whichever tab shows
        self.frames += 1
