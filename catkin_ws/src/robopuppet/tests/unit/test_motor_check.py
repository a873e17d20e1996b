"""The sign_motor check (calibration.motor_check) on a fake puppet: one joint whose motor is
wired the wrong way, a PID clamped to the voltage limits the check stored, time passed in."""
import math

import pytest

from robopuppet import settings
from robopuppet.calibration import motor_check
from robopuppet.config import config_store

SAFE_V = 1.5  # the check's promise, written out
WRONG = 5


class FakePuppet:
    """Joints that turn at 0.5 rad/s per V of PID voltage (kp 20 V/rad), clamped to the stored
    limits; joint WRONG's motor turns the other way. Records every stored value and voltage."""

    def __init__(self, angle_max=1.5):
        self.stored = config_store.defaults()
        for joint in settings.JOINTS:
            self.stored[joint].update(voltage_min=-7.2, voltage_max=7.2, angle_max=angle_max)
        self.angles = [0.1 * j for j in settings.JOINTS]
        self.setpoints = list(self.angles)
        self.opmode = 'limp'
        self.volts = [0.0] * 7
        self.stores, self.most_v, self.fail_store = [], 0.0, None

    def step(self, dt_s):
        for j in settings.JOINTS:
            cfg = self.stored[j]
            volts = 0.0
            if self.opmode == 'hold':
                volts = min(max(20.0 * (self.setpoints[j] - self.angles[j]), cfg['voltage_min']),
                            cfg['voltage_max'])
            self.volts[j] = volts
            self.most_v = max(self.most_v, abs(volts))
            self.angles[j] += 0.5 * volts * dt_s * (-1.0 if j == WRONG else 1.0)

    def do(self, command):
        if command.kind in ('limp', 'hold'):
            self.opmode = command.kind
            self.setpoints = list(self.angles)
        elif command.kind == 'setpoint':
            self.setpoints[command.joint] = command.values
        elif command.kind == 'store':
            assert self.opmode == 'limp', 'limits change only while limp'
            self.stores.append(command.values)
            if self.fail_store == len(self.stores):
                return 'config node gone'
            for joint, values in command.values.items():
                self.stored[joint].update(values)
        return None


def run(puppet, check, until_s=120.0, on_tick=None):
    """Drive the check at 10 Hz until it is done; return the time it took (s)."""
    t, error = 0.0, puppet.do(check.start())
    check_error = check.stored(t, error or '')
    puppet.do(check_error)
    while check.phase != 'done' and t < until_s:
        t += 0.1
        for _ in range(10):
            puppet.step(0.01)
        if on_tick:
            on_tick(t)
        command = check.update(t, puppet.angles, puppet.volts)
        error = puppet.do(command)
        if command.kind == 'store':
            puppet.do(check.stored(t, error or ''))
    return t


def test_the_check_finds_the_wrong_motor_within_the_safe_voltage_and_restores():
    puppet = FakePuppet()
    original = {j: dict(puppet.stored[j]) for j in settings.JOINTS}
    check = motor_check.MotorCheck(puppet.stored)
    run(puppet, check)
    assert check.error == ''
    assert check.results == {j: 'wrong' if j == WRONG else 'right' for j in settings.JOINTS}
    assert check.wrong() == [WRONG]
    assert puppet.most_v <= SAFE_V
    for values in puppet.stores[:-1]:  # one joint powered at a time, the others at 0 V
        powered = [j for j, v in values.items() if v != {'voltage_min': 0.0, 'voltage_max': 0.0}]
        assert len(powered) == 1
        assert values[powered[0]] == {'voltage_min': -SAFE_V, 'voltage_max': SAFE_V}
    assert puppet.stored == original and puppet.opmode == 'limp'
    assert check.flips([WRONG]) == {WRONG: {'sign_motor': -1.0}}


def test_a_joint_near_its_maximum_steps_down():
    puppet = FakePuppet(angle_max=0.65)  # joints 5, 6 start within 0.2 rad of it
    check = motor_check.MotorCheck(puppet.stored)
    run(puppet, check)
    assert check.results == {j: 'wrong' if j == WRONG else 'right' for j in settings.JOINTS}
    assert max(puppet.angles) <= 0.65 + 1e-9


def test_a_held_joint_is_reported_as_not_moving():
    puppet = FakePuppet()
    turn = puppet.step

    def step_holding_joint_2(dt_s):
        held = puppet.angles[2]
        turn(dt_s)
        puppet.angles[2] = held
    puppet.step = step_holding_joint_2
    check = motor_check.MotorCheck(puppet.stored)
    run(puppet, check)
    assert check.results[2] == motor_check.UNKNOWN and check.results[0] == 'right'


@pytest.mark.parametrize('cancel_at_s', [0.5, 2.0, 8.0])
def test_cancel_limps_and_restores(cancel_at_s):
    puppet = FakePuppet()
    original = {j: dict(puppet.stored[j]) for j in settings.JOINTS}
    check = motor_check.MotorCheck(puppet.stored)

    def cancel(t):
        if abs(t - cancel_at_s) < 0.05:
            puppet.do(check.cancel())
            assert puppet.opmode == 'limp'
    run(puppet, check, on_tick=cancel)
    assert check.error == 'cancelled' and check.phase == 'done'
    assert puppet.stored == original and puppet.opmode == 'limp'


def test_a_failed_store_stops_the_check_and_restores():
    puppet = FakePuppet()
    original = {j: dict(puppet.stored[j]) for j in settings.JOINTS}
    puppet.fail_store = 3  # the limits for the third joint cannot be stored
    check = motor_check.MotorCheck(puppet.stored)
    run(puppet, check)
    assert 'config node gone' in check.error
    assert sorted(check.results) == [0, 1]
    assert puppet.stored == original and puppet.opmode == 'limp'


def test_a_voltage_above_the_safe_one_limps_at_once():
    puppet = FakePuppet()
    check = motor_check.MotorCheck(puppet.stored)
    puppet.do(check.start())
    puppet.do(check.stored(0.0))
    puppet.stored[0].update(voltage_min=-7.2, voltage_max=7.2)  # the limit never arrived
    t = 0.0
    while check.phase not in ('restore', 'done') and t < 20.0:
        t += 0.1
        for _ in range(10):  # joint 0 is held: its PID voltage grows past the safe one
            held = puppet.angles[0]
            puppet.step(0.01)
            puppet.angles[0] = held
        puppet.do(check.update(t, puppet.angles, puppet.volts))
    assert 'above the safe' in check.error and puppet.opmode == 'limp'
    assert check.update(t, puppet.angles, puppet.volts).values == check.restore_values()


def test_restoring_failure_is_reported():
    check = motor_check.MotorCheck(FakePuppet().stored)
    check.cancel()
    assert check.update(0.0, [0.0] * 7, [0.0] * 7).kind == 'store'
    check.stored(0.0, 'config node gone')
    assert check.phase == 'done' and 'restoring the voltage limits failed' in check.error
    assert math.isfinite(check.restore_values()[0]['voltage_max'])
