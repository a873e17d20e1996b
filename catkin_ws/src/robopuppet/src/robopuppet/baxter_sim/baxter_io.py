"""Baxter's digital IO, navigators, analog IO and head, as the stand-in models them.

Pure: no rospy, no messages, no clock (the head takes `now_s`, s). Component names are the
Rethink SDK 1.2's: baxter_interface.DigitalIO('<side>_lower_cuff'), Navigator('<location>')
with its lights '<location>_inner_light' and '<location>_outer_light',
AnalogIO('<side>_hand_range') and AnalogIO('torso_fan'). States are dicts of message fields
(DigitalIOState, NavigatorState, AnalogIOState, HeadState).
"""
from robopuppet.baxter_sim.baxter_gripper import approach
from robopuppet.baxter_sim.baxter_refusals import CommandError, brief, finite
from robopuppet.interface import BAXTER_SIDES

NAVIGATORS = ('left', 'right', 'torso_left', 'torso_right')  # the SDK's Navigator locations
# A navigator's buttons in NavigatorState order (its button_names): button0 (wheel press),
# button1, button2; its lights (light_names), which the SDK 1.2 finds by name. Rethink's own
# simulator (baxter_sim_io 1.2.0) publishes the same names.
NAVIGATOR_BUTTONS = ('ok', 'back', 'show')
NAVIGATOR_LIGHTS = ('inner', 'outer')
# The cuff's squeeze sensor and its two buttons (upper: 'dash', lower: 'circle'), the shoulder's.
CUFF_INPUTS = ('lower_cuff', 'upper_button', 'lower_button', 'shoulder_button')


def button_name(location, button):
    """Return the digital input name of a navigator's button ('left_button_ok')."""
    return '%s_button_%s' % (location, button)


def light_name(location, light):
    """Return the digital output name of a navigator's light ('left_inner_light')."""
    return '%s_%s_light' % (location, light)


DIGITAL_INPUTS = tuple(['%s_%s' % (side, name) for side in BAXTER_SIDES for name in CUFF_INPUTS]
                       + [button_name(nav, b) for nav in NAVIGATORS for b in NAVIGATOR_BUTTONS])
DIGITAL_OUTPUTS = tuple(light_name(nav, light) for nav in NAVIGATORS
                        for light in NAVIGATOR_LIGHTS)
ANALOG_INPUTS = tuple('%s_hand_range' % side for side in BAXTER_SIDES)
# The torso's fan: an analog output, its speed 0..100 % (the SDK's analog_io_rampup ramps it so).
ANALOG_OUTPUTS = ('torso_fan',)
FAN_MAX = 100
# The hand's IR range sensor with nothing in reach (the stand-in sees no objects).
RANGE_NOTHING_IN_REACH = 65535.0
# DigitalIOState.PRESSED / UNPRESSED (= ON / OFF); HeadPanCommand's enable_pan_request values.
PRESSED, UNPRESSED = 1, 0
REQUEST_PAN_DISABLE, REQUEST_PAN_ENABLE, REQUEST_PAN_VOID = 0, 1, 2
NOD_DURATION_S = 1.0      # one nod, as Rethink's own simulator times it


def _bool(value, what):
    if not isinstance(value, bool):
        raise CommandError('%s must be true or false, got %s' % (what, brief(value)), 'bad value')
    return value


class DigitalIO:
    """Every digital input and output of the robot, and its navigators; all start off.

    Inputs change only through press() (the simulated hand of a user), outputs through command().
    """

    def __init__(self):
        self.states = dict.fromkeys(DIGITAL_INPUTS + DIGITAL_OUTPUTS, False)
        self.wheels = dict.fromkeys(NAVIGATORS, 0)

    def command(self, name, value):
        """Switch an output (a DigitalOutputCommand: name, value).

        Raises:
            CommandError: an unknown component, an input, or a value that is not a bool.
        """
        self._set(name, value, 'output', 'an input: it is pressed, not commanded', 'input only')

    def press(self, name, value):
        """Press (True) or release (False) an input: a cuff squeeze or a button.

        Raises:
            CommandError: an unknown component, an output, or a value that is not a bool.
        """
        self._set(name, value, 'input', 'an output: switch it on /robot/digital_io/command',
                  'not an input')

    def _set(self, name, value, kind, other, reason):
        """Set a component of `kind` ('input' or 'output'); refuse one of the other kind with
        'is <other>' and `reason`."""
        if name not in (DIGITAL_INPUTS if kind == 'input' else DIGITAL_OUTPUTS):
            if name in self.states:
                raise CommandError('digital io %s is %s' % (name, other), reason)
            raise CommandError('no digital io component %s' % brief(name), 'unknown component')
        self.states[name] = _bool(value, 'digital %s %s' % (kind, name))

    def digital_states(self):
        """Return {component name: DigitalIOState fields}."""
        return {name: dict(state=PRESSED if on else UNPRESSED,
                           isInputOnly=name not in DIGITAL_OUTPUTS)
                for name, on in self.states.items()}

    def navigator_states(self):
        """Return {navigator location: NavigatorState fields} (wheel 0..255)."""
        return {nav: dict(button_names=list(NAVIGATOR_BUTTONS),
                          buttons=[self.states[button_name(nav, b)] for b in NAVIGATOR_BUTTONS],
                          wheel=self.wheels[nav],
                          light_names=list(NAVIGATOR_LIGHTS),
                          lights=[self.states[light_name(nav, light)]
                                  for light in NAVIGATOR_LIGHTS])
                for nav in NAVIGATORS}


class AnalogIO:
    """The analog components: the hands' range sensors (inputs, nothing in reach) and the torso
    fan (an output, 0 at start)."""

    def __init__(self):
        self.outputs = dict.fromkeys(ANALOG_OUTPUTS, 0)

    def command(self, name, value):
        """Set an output (an AnalogOutputCommand: name, value 0..FAN_MAX).

        Raises:
            CommandError: an unknown component, an input, or a value out of range.
        """
        if name not in self.outputs:
            if name in ANALOG_INPUTS:
                raise CommandError('analog io %s is an input: it is read, not commanded' % name,
                                   'input only')
            raise CommandError('no analog io component %s' % brief(name), 'unknown component')
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= FAN_MAX:
            raise CommandError('analog output %s takes 0..%d, got %s' % (name, FAN_MAX,
                                                                        brief(value)), 'bad value')
        self.outputs[name] = value

    def states(self):
        """Return {component name: AnalogIOState fields but the timestamp}."""
        states = {name: dict(value=RANGE_NOTHING_IN_REACH, isInputOnly=True)
                  for name in ANALOG_INPUTS}
        states.update((name, dict(value=float(value), isInputOnly=False))
                      for name, value in self.outputs.items())
        return states


class Head:
    """The head: pan toward a target at a commanded speed, and nod.

    Args:
        limit: the head_pan JointLimit (rad, rad/s); speed_ratio 1 is its velocity limit.
        now_s: the start time (s).
    """

    def __init__(self, limit, now_s):
        self.limit = limit
        self.pan_rad = self.target_rad = 0.0
        self.speed_rad_s = 0.0      # the commanded pan speed
        self.velocity_rad_s = 0.0   # the measured one, of the last step
        self.pan_enabled = True
        self.nod_until_s = None
        self._nod_requested = False
        self.last_step_s = now_s

    def command_pan(self, target_rad, speed_ratio, enable_pan_request):
        """A HeadPanCommand: pan to target (clamped to the limits) at speed_ratio (0..1).

        enable_pan_request 0 disables panning (the head then holds and ignores targets), 1
        enables it, 2 leaves it.

        Raises:
            CommandError: a non-finite target or ratio, a ratio outside 0..1, or an
                enable_pan_request other than 0, 1, 2; nothing changes then.
        """
        target_rad = finite(target_rad, 'head pan target', 'non-finite value')
        ratio = finite(speed_ratio, 'head pan speed_ratio', 'non-finite value')
        if not 0.0 <= ratio <= 1.0:
            raise CommandError('head pan speed_ratio must be within 0..1, got %g' % ratio,
                               'out of range')
        if enable_pan_request not in (REQUEST_PAN_DISABLE, REQUEST_PAN_ENABLE, REQUEST_PAN_VOID):
            raise CommandError('head pan enable_pan_request must be 0, 1 or 2, got %s'
                               % brief(enable_pan_request), 'bad value')
        if enable_pan_request != REQUEST_PAN_VOID:
            self.pan_enabled = enable_pan_request == REQUEST_PAN_ENABLE
        if self.pan_enabled:
            self.target_rad = min(self.limit.upper, max(self.limit.lower, target_rad))
            self.speed_rad_s = ratio * self.limit.velocity
        else:
            self.hold()

    def command_nod(self, nod):
        """A command_head_nod: True starts one nod (unless nodding), False is ignored.

        Raises:
            CommandError: nod is not a bool.
        """
        self._nod_requested |= _bool(nod, 'head nod')

    def hold(self):
        """Stop panning where the head is."""
        self.target_rad = self.pan_rad

    def step(self, now_s, enabled):
        """Pan and nod until now_s; the head moves only while the robot is enabled."""
        dt = now_s - self.last_step_s
        if dt <= 0.0:
            return
        self.last_step_s = now_s
        old = self.pan_rad
        if enabled:
            self.pan_rad = approach(old, self.target_rad, self.speed_rad_s * dt, 1.0)
            if self._nod_requested and self.nod_until_s is None:
                self.nod_until_s = now_s + NOD_DURATION_S
        self._nod_requested = False
        if self.nod_until_s is not None and now_s >= self.nod_until_s:
            self.nod_until_s = None
        self.velocity_rad_s = (self.pan_rad - old) / dt

    def state(self):
        """Return the HeadState fields (pan rad)."""
        return dict(pan=self.pan_rad, isTurning=self.pan_rad != self.target_rad,
                    isNodding=self.nod_until_s is not None, isPanEnabled=self.pan_enabled)
