"""A simulated puppet controller: the 2020 firmware's control loop and encoders, on the arm model.

Pure: time is an argument, no clock, no I/O, no rospy. PuppetFirmware does what the 2020
firmware does (its code: doates625/RoboPuppet; docs/serial.md, "puppet_sim_X"):
heartbeat about every second and state sets at the state rate from power-on, and a 50 Hz control
loop that reads the encoders, clamps each angle to [angle_min, angle_max], limits its rate to
[velocity_min, velocity_max] and, in hold, runs one PID per joint on the wrapped error between
the setpoint and the encoder angle, clamped to [voltage_min, voltage_max].

Encoders (puppet_encoders): reported angle = sign_angle x wrap(raw - stored_home), where
stored_home is home_angle x the sign_angle in force when the home frame arrived (so a host must
send the sign first); a disconnected hall encoder reports angle 0. Home applies to an
uncalibrated quadrature encoder's count from power-on all the same.

Opmode: limp zeroes every setpoint and voltage; hold resets the PIDs and keeps the setpoints (0
rad after power-on or limp). The settings start at the firmware's power-on values
(POWER_ON_SETTINGS: velocity limits +-pi/4 rad/s, voltage limits 0 V) until the host loads its
own. The bytes on the wire are robopuppet.puppet_sim.puppet_wire's.
"""
import collections
import math
import reprlib

import numpy as np

from robopuppet import interface, settings
from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_arm import (NOMINAL_VOLTAGE_V, REST_GRIPPERS, REST_POSE_RAD,
                                              ArmPhysics, wrap)
from robopuppet.puppet_sim.puppet_encoders import Encoders

CONTROL_RATE_HZ = 50.0
HEARTBEAT_RATE_HZ = 1.0
PHYSICS_STEPS_PER_TICK = 10
CATCH_UP_S = 0.5  # a late advance() runs at most this much of the missed time
TIE_S = 1e-9  # times this close are one time (sums of periods drift from the multiples)
CONTROL_LOG_TICKS = 500  # ControlTicks kept for take_control_ticks() (10 s at 50 Hz)

# The firmware's settings at power-on, before the host loads any (AngleFilters, Controllers,
# Encoders and Motors init()): PID limits and gains all 0, so hold pushes nothing until loaded.
POWER_ON_SETTINGS = dict(zip(settings.NAMES, (
    0.0,                           # home_angle
    -math.pi / 2, math.pi / 2,     # angle_min, angle_max
    -math.pi / 4, math.pi / 4,     # velocity_min, velocity_max
    0.0, 0.0,                      # voltage_min, voltage_max
    0.0, 0.0, 0.0,                 # pid_kp, pid_ki, pid_kd
    1.0, 1.0)))                    # sign_angle, sign_motor

ControlTick = collections.namedtuple('ControlTick', 'time_s setpoint_rad angle_rad voltage_v')


class PuppetFirmware:
    """The puppet's microcontroller (the 2020 firmware) and arm; feed it host frames and time.

    Use: set_opmode / configure / set_setpoint for each host frame (puppet_wire.FirmwareReceiver
    calls them as the firmware's receive logic does; handle() takes codec messages), advance(now)
    to run the control loop up to now and collect the frames due (heartbeat, state sets),
    take_control_ticks() for what each control tick in hold did, and the set_* operator methods.

    Args:
        state_rate_hz: rate of the state sets (the 2020 firmware's constant is 10 Hz).
        pose_rad: the arm's mechanical pose at power-on.
        hall_disconnected: absolute-encoder joints (of 1, 3, 5) missing at power-on: they
            report Disconnected and angle 0 for good.
    """

    def __init__(self, state_rate_hz=10.0, pose_rad=REST_POSE_RAD, hall_disconnected=()):
        if not state_rate_hz > 0.0:
            raise ValueError('state rate must be positive, got %r' % (state_rate_hz,))
        n = settings.NUM_JOINTS
        self.state_period_s = 1.0 / state_rate_hz
        self.encoders = Encoders(pose_rad, hall_disconnected)
        self.arm = ArmPhysics(pose_rad)
        self.config = {j: dict(POWER_ON_SETTINGS) for j in settings.JOINTS}  # last value per id
        self.stored_home_rad = [0.0] * n  # home_angle x the sign_angle when it arrived
        self.opmode = codec.LIMP
        self.encoder_rad = [0.0] * n   # sign_angle x encoder angle (what the PID uses)
        self.angle_rad = [0.0] * n     # after the angle filter (what the host is sent)
        self._filter_started = False
        self.setpoint_rad = [0.0] * n
        self.voltage_v = [0.0] * n
        self._integral = [0.0] * n
        self._last_error = [None] * n
        self.ignored_frames = 0  # for a joint out of range (the firmware's would be undefined)
        self._ticks = collections.deque(maxlen=CONTROL_LOG_TICKS)
        self.button = 0
        self.grippers = list(REST_GRIPPERS)
        self._time_s = None
        self._next_control_s = self._next_state_s = self._next_heartbeat_s = None

    # Operator -------------------------------------------------------------------------------
    def set_hand(self, positions_rad):
        """Move the hand toward {joint: mechanical angle rad}; None or NaN lets go of a joint."""
        for joint, angle in positions_rad.items():
            self.arm.set_hand(joint, angle if angle is not None and math.isfinite(angle)
                              else None)

    def set_button(self, button):
        """Hold user button 1-4 down, or none (0). Raises ValueError for another value."""
        if button not in range(interface.NUM_BUTTONS + 1):
            raise ValueError('button must be 0-%d, got %r' % (interface.NUM_BUTTONS, button))
        self.button = button

    def set_grippers(self, readings):
        """Set the four gripper readings, each clamped to 0-1. Raises ValueError otherwise."""
        if len(readings) != interface.NUM_GRIPPERS or not all(math.isfinite(r) for r in readings):
            raise ValueError('need %d finite gripper readings, got %s'
                             % (interface.NUM_GRIPPERS, reprlib.repr(list(readings))))
        self.grippers = [min(1.0, max(0.0, r)) for r in readings]

    # Host frames (the firmware's receive callbacks; fields are not range-checked) ------------
    def set_opmode(self, mode):
        """Opmode byte: 0x01 holds (PIDs reset, setpoints kept), anything else goes limp."""
        if mode == codec.HOLD:
            self.opmode = codec.HOLD
            self._integral = [0.0] * settings.NUM_JOINTS
            self._last_error = [None] * settings.NUM_JOINTS
        else:
            self.opmode = codec.LIMP
            self.setpoint_rad = [0.0] * settings.NUM_JOINTS
            self.voltage_v = [0.0] * settings.NUM_JOINTS

    def configure(self, joint, config_id, value):
        """Store one setting; config ids above 11 are ignored, as the firmware does."""
        if joint not in settings.JOINTS:
            self.ignored_frames += 1
            return
        if config_id >= len(settings.NAMES):
            return
        name = settings.NAMES[config_id]
        self.config[joint][name] = value
        if name == 'home_angle':
            self.stored_home_rad[joint] = value * self.config[joint]['sign_angle']

    def set_setpoint(self, joint, angle_rad):
        """Set a joint's setpoint, clamped to its angle limits."""
        if joint not in settings.JOINTS:
            self.ignored_frames += 1
            return
        cfg = self.config[joint]
        self.setpoint_rad[joint] = _clamp(angle_rad, cfg['angle_min'], cfg['angle_max'])

    def handle(self, message):
        """Obey one decoded host->device codec message; ignore device->host types."""
        if isinstance(message, codec.Opmode):
            self.set_opmode(message.mode)
        elif isinstance(message, codec.JointConfig):
            self.configure(*message)
        elif isinstance(message, codec.JointSetpoint):
            self.set_setpoint(*message)

    # Time -----------------------------------------------------------------------------------
    def advance(self, now_s):
        """Run the control loop up to now_s; return the messages the device sends by then.

        The first call is power-on: control ticks start one period later, state sets one
        state period later and heartbeats one second later. Everything due runs in time order
        (a state set reports the arm at its own time), as on the device's own clock: a late
        call (the simulator's process not scheduled for a while) sends every state set and
        heartbeat the firmware would have sent meanwhile, so their rate does not depend on
        the host machine's load. A stall longer than CATCH_UP_S is not caught up.
        """
        if self._time_s is None:
            self._next_control_s = now_s + 1.0 / CONTROL_RATE_HZ
            self._next_state_s = now_s + self.state_period_s
            self._next_heartbeat_s = now_s + 1.0 / HEARTBEAT_RATE_HZ
        # A host that stalls for long does not make the arm catch up in one burst.
        self._next_control_s = _not_before(self._next_control_s, 1.0 / CONTROL_RATE_HZ,
                                           now_s - CATCH_UP_S)
        self._next_state_s = _not_before(self._next_state_s, self.state_period_s,
                                         now_s - CATCH_UP_S)
        self._next_heartbeat_s = _not_before(self._next_heartbeat_s, 1.0 / HEARTBEAT_RATE_HZ,
                                             now_s - CATCH_UP_S)
        out = []
        while True:
            due_s = min(self._next_control_s, self._next_heartbeat_s, self._next_state_s)
            if due_s > now_s + TIE_S:
                break
            tie_s = due_s + TIE_S  # at one time: the tick first (what is sent reflects it)
            if self._next_control_s <= tie_s:
                self._control_tick(due_s, 1.0 / CONTROL_RATE_HZ)
                self._next_control_s += 1.0 / CONTROL_RATE_HZ
            elif self._next_heartbeat_s <= tie_s:
                out.append(codec.Heartbeat())
                self._next_heartbeat_s += 1.0 / HEARTBEAT_RATE_HZ
            else:
                out.extend(self.state_messages())
                self._next_state_s += self.state_period_s
        self._time_s = now_s
        return out

    def next_due_s(self):
        """Return the time at which advance() next has work to do (None before the first call)."""
        if self._time_s is None:
            return None
        return min(self._next_control_s, self._next_state_s, self._next_heartbeat_s)

    def take_control_ticks(self):
        """Return and forget the ControlTick of each control tick run in hold since last time."""
        ticks = list(self._ticks)
        self._ticks.clear()
        return ticks

    def state_messages(self):
        """Return one state set: seven joint states, four grippers, then the buttons."""
        out = [codec.JointState(j, self.encoders.status(j), self.angle_rad[j], self.voltage_v[j])
               for j in settings.JOINTS]
        out.extend(codec.Gripper(g, r) for g, r in enumerate(self.grippers))
        out.append(codec.Buttons(self.button))
        return out

    def _encoder(self, joint):
        """Return sign_angle x the encoder's angle: wrap(raw - stored home), as the firmware."""
        raw = self.encoders.raw_rad(joint, self.arm.angle_rad[joint])
        if raw is None:
            return self.config[joint]['sign_angle'] * 0.0
        return self.config[joint]['sign_angle'] * wrap(raw - self.stored_home_rad[joint])

    def _control_tick(self, time_s, dt_s):
        """One 50 Hz firmware cycle: encoders, angle filters, PIDs; then the arm moves dt_s."""
        hold = self.opmode == codec.HOLD
        for joint in settings.JOINTS:
            cfg = self.config[joint]
            self.encoder_rad[joint] = self._encoder(joint)
            angle = _clamp(self.encoder_rad[joint], cfg['angle_min'], cfg['angle_max'])
            if self._filter_started:
                previous = self.angle_rad[joint]
                angle = previous + _clamp(angle - previous, cfg['velocity_min'] * dt_s,
                                          cfg['velocity_max'] * dt_s)
            self.angle_rad[joint] = angle
        self._filter_started = True
        applied = np.zeros(settings.NUM_JOINTS)
        if hold:
            for joint in settings.JOINTS:
                self.voltage_v[joint] = self._pid(joint, dt_s)
                volts = self.voltage_v[joint] * self.config[joint]['sign_motor']
                if math.isfinite(volts):  # the PWM duty saturates at the supply voltage
                    applied[joint] = min(NOMINAL_VOLTAGE_V, max(-NOMINAL_VOLTAGE_V, volts))
            self._ticks.append(ControlTick(time_s, tuple(self.setpoint_rad),
                                           tuple(self.angle_rad), tuple(self.voltage_v)))
        self.arm.update_loads()
        self.arm.update_hand(dt_s, hold)
        sub_dt = dt_s / PHYSICS_STEPS_PER_TICK
        for _ in range(PHYSICS_STEPS_PER_TICK):
            self.encoders.move(self.arm.step(sub_dt, applied, hold), self.arm.angle_rad)

    def _pid(self, joint, dt_s):
        """Return the PID voltage of a joint on the encoder angle, clamped (anti-windup)."""
        cfg = self.config[joint]
        error = wrap(self.setpoint_rad[joint] - self.encoder_rad[joint])
        last = self._last_error[joint]
        derivative = 0.0 if last is None else wrap(error - last) / dt_s
        self._last_error[joint] = error
        integral = self._integral[joint] + error * dt_s
        volts = cfg['pid_kp'] * error + cfg['pid_ki'] * integral + cfg['pid_kd'] * derivative
        clamped = _clamp(volts, cfg['voltage_min'], cfg['voltage_max'])
        if clamped == volts:
            self._integral[joint] = integral
        return clamped


def _clamp(value, low, high):
    """Clamp as the firmware's CppUtil does: NaN passes through."""
    return low if value < low else high if value > high else value


def _not_before(due_s, period_s, earliest_s):
    """Return due_s moved on by whole periods to at or after earliest_s (missed ones skipped)."""
    if due_s >= earliest_s:
        return due_s
    return due_s + math.ceil((earliest_s - due_s) / period_s) * period_s
