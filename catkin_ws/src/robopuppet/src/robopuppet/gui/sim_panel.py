"""The virtual puppet panel: move the simulated puppet's hand and press its buttons."""
import math
import time

from PyQt5 import QtCore, QtWidgets

from robopuppet import interface, settings
from robopuppet.puppet_sim.puppet_arm import REST_GRIPPERS, REST_POSE_RAD

SLIDER_STEPS_PER_RAD = 1000  # slider resolution: 1 mrad
GRIPPER_STEPS = 100
# The simulated firmware samples the buttons once per state set (interface.DEFAULT_COMM_RATE_HZ,
# 10 Hz): a click shorter than that could fall between two sets and be lost, so a button stays
# pressed for at least two state periods, however short the click.
MIN_PRESS_S = 2.0 / interface.DEFAULT_COMM_RATE_HZ


class SimPanel(QtWidgets.QGroupBox):
    """Sliders and buttons that publish through a SimPuppetClient-like `sim`.

    The sim needs set_hand(seven angles rad, NaN = let go), set_button(1-4 or 0) and
    set_grippers(four readings 0-1). The controls start where the simulated puppet starts (its
    rest pose, held by the hand) and publish only when the operator uses them. 'Let go' takes
    the hand off every joint (so that hold mode or the arm controller can move the puppet); a
    slider puts it back on its joint. The buttons act while held down, like the puppet's own,
    and at least MIN_PRESS_S (a click of 0 ms is held that long, so the firmware sees it).
    `clock` (s, monotonic) is for tests.
    """

    def __init__(self, sim, parent=None, clock=time.monotonic):
        super().__init__('Virtual puppet', parent)
        self._sim = sim
        self._clock = clock
        self._button = 0  # the user button the panel holds down (1-4), 0 none
        self._end_piece = False  # whether the panel holds the end-piece button down
        self._pressed_s = {}  # 'user' / 'end piece': when it was last pressed (clock, s)
        self._releases = {}  # the same keys: the QTimer that releases it when due
        self.joint_sliders = []
        self.gripper_sliders = []
        self._value_labels = []
        self._engaged = [True] * settings.NUM_JOINTS
        grid = QtWidgets.QGridLayout()
        for joint in settings.JOINTS:
            slider = self._slider(-math.pi * SLIDER_STEPS_PER_RAD, math.pi * SLIDER_STEPS_PER_RAD)
            slider.setSingleStep(10)
            slider.setPageStep(100)
            label = QtWidgets.QLabel()
            label.setMinimumWidth(80)
            slider.setValue(int(round(REST_POSE_RAD[joint] * SLIDER_STEPS_PER_RAD)))
            slider.valueChanged.connect(lambda _, j=joint: self._hand_changed(j))
            slider.sliderPressed.connect(lambda j=joint: self._hand_changed(j))
            grid.addWidget(QtWidgets.QLabel('joint %d' % joint), joint, 0)
            grid.addWidget(slider, joint, 1)
            grid.addWidget(label, joint, 2)
            self.joint_sliders.append(slider)
            self._value_labels.append(label)
        self.let_go_button = QtWidgets.QPushButton('let go of the puppet')
        self.let_go_button.clicked.connect(self.let_go)
        grid.addWidget(self.let_go_button, settings.NUM_JOINTS, 1)
        for gripper in range(interface.END_PIECE_GRIPPER):
            slider = self._slider(0, GRIPPER_STEPS)
            slider.setValue(int(round(REST_GRIPPERS[gripper] * GRIPPER_STEPS)))
            slider.valueChanged.connect(self._grippers_changed)
            grid.addWidget(QtWidgets.QLabel('gripper %d' % gripper),
                           settings.NUM_JOINTS + 1 + gripper, 0)
            grid.addWidget(slider, settings.NUM_JOINTS + 1 + gripper, 1)
            self.gripper_sliders.append(slider)
        self.user_buttons = []
        buttons = QtWidgets.QHBoxLayout()
        for button in range(1, interface.NUM_BUTTONS + 1):
            widget = QtWidgets.QPushButton('button %d' % button)
            widget.setToolTip('held down while pressed (1: limp/hold, 2: left follows, '
                              '3: right follows)')
            widget.pressed.connect(lambda b=button: self._press_button(b))
            widget.released.connect(lambda b=button: self._release('user', b))
            buttons.addWidget(widget)
            self.user_buttons.append(widget)
        self.end_piece_button = QtWidgets.QPushButton('end-piece button (grip)')
        self.end_piece_button.pressed.connect(self._press_end_piece)
        self.end_piece_button.released.connect(lambda: self._release('end piece', True))
        layout = QtWidgets.QVBoxLayout(self)
        layout.addLayout(grid)
        layout.addLayout(buttons)
        layout.addWidget(self.end_piece_button)
        layout.addStretch(1)
        self._show_angles()

    @staticmethod
    def _slider(low, high):
        slider = QtWidgets.QSlider(QtCore.Qt.Horizontal)
        slider.setRange(int(round(low)), int(round(high)))
        slider.setMinimumWidth(160)
        return slider

    def angles(self):
        """Return the seven hand angles in rad, NaN where the hand has let go."""
        return [s.value() / SLIDER_STEPS_PER_RAD if engaged else math.nan
                for s, engaged in zip(self.joint_sliders, self._engaged)]

    def set_angle(self, joint, angle_rad):
        """Move a joint's slider (publishes the hand)."""
        self.joint_sliders[joint].setValue(int(round(angle_rad * SLIDER_STEPS_PER_RAD)))

    def let_go(self):
        """Take the hand off every joint."""
        self._engaged = [False] * settings.NUM_JOINTS
        self._sim.set_hand(self.angles())
        self._show_angles()

    def _hand_changed(self, joint):
        self._engaged[joint] = True
        self._sim.set_hand(self.angles())
        self._show_angles()

    def _show_angles(self):
        for label, angle_rad in zip(self._value_labels, self.angles()):
            label.setText('let go' if math.isnan(angle_rad) else '%+.3f rad' % angle_rad)

    def _press_button(self, button):
        self._cancel_release('user')
        self._pressed_s['user'], self._button = self._clock(), button
        self._sim.set_button(button)

    def _press_end_piece(self):
        self._cancel_release('end piece')
        self._pressed_s['end piece'], self._end_piece = self._clock(), True
        self._grippers_changed()

    def _release(self, key, pressed):
        """Release a button now, or once it has been down MIN_PRESS_S (pressed: which)."""
        left_s = MIN_PRESS_S - (self._clock() - self._pressed_s[key])
        if left_s <= 0.0:
            self._let_up(key, pressed)
            return
        timer = QtCore.QTimer(self)
        timer.setSingleShot(True)
        timer.setTimerType(QtCore.Qt.PreciseTimer)  # a coarse timer may fire 5 % early
        timer.timeout.connect(lambda: self._let_up(key, pressed))
        timer.start(int(math.ceil(left_s * 1000.0)))
        self._releases[key] = timer

    def _cancel_release(self, key):
        timer = self._releases.pop(key, None)
        if timer is not None:
            timer.stop()
            timer.deleteLater()

    def _let_up(self, key, pressed):
        self._cancel_release(key)
        if key == 'end piece':
            self._end_piece = False
            self._grippers_changed()
        elif self._button == pressed:  # not another button pressed since
            self._button = 0
            self._sim.set_button(0)

    def _grippers_changed(self):
        readings = [s.value() / GRIPPER_STEPS for s in self.gripper_sliders]
        readings.append(0.0 if self._end_piece else 1.0)
        self._sim.set_grippers(readings)
