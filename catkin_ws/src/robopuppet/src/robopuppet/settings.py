"""The puppet's joint settings (twelve per joint, as in 2020): one table, used by every node.

A setting's index in SETTINGS is its config id on the wire (serial frame 0x30) and its field
order in the GetConfig response. Its [low, high] is what the puppet's hardware can take (both
inclusive), and bound_source says where that bound comes from: a value outside it, or a range
of a joint that breaks its rule, is refused by the config node, the GUI and the serial node
(implausible() and range_problems(): the one check of each) and never reaches the puppet.
"""
import collections
import math
import struct
import zlib

from robopuppet.float32 import format_value, to_float32

NUM_JOINTS = 7
JOINTS = tuple(range(NUM_JOINTS))
JOINT_NAMES = tuple('joint_%d' % j for j in JOINTS)  # sensor_msgs/JointState names
# The puppet's encoders: quadrature on the twist joints (Uncalibrated until turned through their
# index mark), hall (absolute) on the rotary joints.
QUAD_JOINTS, HALL_JOINTS = (0, 2, 4, 6), (1, 3, 5)

# The hardware behind the bounds (2020 MQP report: power supply, encoders, motors).
MOTOR_SUPPLY_V = 7.2  # the buck-boost rail of the seven servo motors is set to 7.2 V
MAX_GAIN = 1e4  # 1e4 V/rad gives the whole 7.2 V at 0.72 mrad, under 2 counts of the finest
#                 encoder (AS5048B, 14 bit: 0.38 mrad); a larger gain is only bang-bang
MAX_SPEED_RAD_S = 4 * math.pi  # two turns a second: more than a hand turns a puppet joint

Setting = collections.namedtuple('Setting', 'name unit default meaning low high bound_source')

SETTINGS = (
    Setting('home_angle', 'rad', 0.0, 'angle zero offset', -2 * math.pi, 2 * math.pi,
            'within one turn'),
    Setting('angle_min', 'rad', -1.571, 'minimum angle', -math.pi, math.pi,
            'the firmware wraps angles into [-pi, pi]'),
    Setting('angle_max', 'rad', 1.571, 'maximum angle', -math.pi, math.pi,
            'the firmware wraps angles into [-pi, pi]'),
    Setting('velocity_min', 'rad/s', -6.283, 'minimum angular velocity',
            -MAX_SPEED_RAD_S, MAX_SPEED_RAD_S, 'two turns a second, more than a hand turns'),
    Setting('velocity_max', 'rad/s', 6.283, 'maximum angular velocity',
            -MAX_SPEED_RAD_S, MAX_SPEED_RAD_S, 'two turns a second, more than a hand turns'),
    Setting('voltage_min', 'V', -7.2, 'minimum PID voltage', -MOTOR_SUPPLY_V, MOTOR_SUPPLY_V,
            'the 7.2 V motor supply'),
    Setting('voltage_max', 'V', 7.2, 'maximum PID voltage', -MOTOR_SUPPLY_V, MOTOR_SUPPLY_V,
            'the 7.2 V motor supply'),
    Setting('pid_kp', 'V/rad', 0.0, 'P gain', 0.0, MAX_GAIN,
            'no positive feedback; 7.2 V within 2 encoder counts'),
    Setting('pid_ki', 'V/(rad*s)', 0.0, 'I gain', 0.0, MAX_GAIN,
            'no positive feedback; a sane large bound'),
    Setting('pid_kd', 'V/(rad/s)', 0.0, 'D gain', 0.0, MAX_GAIN,
            'no positive feedback; a sane large bound'),
    Setting('sign_angle', '+1/-1', 1.0, 'direction of angle', -1.0, 1.0, '+1 or -1'),
    Setting('sign_motor', '+1/-1', 1.0, 'direction of motor voltage', -1.0, 1.0, '+1 or -1'),
)

NAMES = tuple(s.name for s in SETTINGS)
CONFIG_ID = {s.name: index for index, s in enumerate(SETTINGS)}
DEFAULTS = {s.name: s.default for s in SETTINGS}
BY_NAME = {s.name: s for s in SETTINGS}

# (min, max) pairs: min must not exceed max.
RANGE_PAIRS = (('angle_min', 'angle_max'),
               ('velocity_min', 'velocity_max'),
               ('voltage_min', 'voltage_max'))
# Pairs whose range must hold 0: the firmware's angle filter moves the reported angle by at
# least velocity_min and at most velocity_max per second, so without 0 the angle drifts for ever
# (out of [-pi, pi], and serial_X drops every set). A voltage range may exclude 0.
ZERO_RANGES = (('velocity_min', 'velocity_max'),)
SIGNS = ('sign_angle', 'sign_motor')
# The settings that change the angle the puppet reports (the 2020 firmware, as puppet_sim does):
# sign_angle x wrap(raw - sign_angle x home_angle), clamped to [angle_min, angle_max], its rate
# limited to [velocity_min, velocity_max]. A change of one moves the reported angle while the
# hand stays still: Baxter must not follow it (docs/teleop.md, "Settings that change the angle").
# The others (voltage limits, PID gains, sign_motor) only change what the motors do.
ANGLE_SETTINGS = ('home_angle', 'sign_angle', 'angle_min', 'angle_max', 'velocity_min',
                  'velocity_max')
ANGLE_TAG_PREFIX = 'angle_settings:'


def angle_tag(joints):
    """Return the text that names the ANGLE_SETTINGS values of joints 0..6 ([{name: value}],
    taken as float32): equal values give equal texts, any change another (a CRC-32).

    serial_X puts the tag of the settings it has begun to send to the device into each
    joint_states' header.frame_id; arm_X follows a sample only when its tag is that of the
    newest stored settings it has heard of (robopuppet.arm.angle_settings).
    """
    values = [to_float32(joints[joint][name]) for joint in JOINTS for name in ANGLE_SETTINGS]
    data = b''.join(struct.pack('<d', value) for value in values)
    return '%s%08x' % (ANGLE_TAG_PREFIX, zlib.crc32(data))


def implausible(name, value):
    """Return why float32 `value` cannot be setting `name` on its own, or '' when it can.

    The reasons: not finite, a sign other than +-1, or outside the setting's bound (the
    message names the bound, its unit and where it comes from).
    """
    if not math.isfinite(value):
        return 'not a finite float32 number'
    if name in SIGNS and value not in (1.0, -1.0):
        return 'a sign must be +1 or -1'
    setting = BY_NAME[name]
    low, high = to_float32(setting.low), to_float32(setting.high)
    if not low <= value <= high:
        return 'outside its bound [%s, %s] %s (%s)' % (
            format_value(low), format_value(high), setting.unit, setting.bound_source)
    return ''


def range_problems(values, given=None, refused=()):
    """Return [(min name, max name, why)] for each range of one joint that breaks its rule.

    The rules: a minimum not above its maximum (RANGE_PAIRS), then a range that holds 0
    (ZERO_RANGES; checked where the minimum is not above the maximum). why reads
    'angle_min = 1.0: above angle_max = 0.5', 'angle_max = -2.0: below angle_min = -1.571' or
    'velocity_min..velocity_max = 0.5..6.283: the range must hold 0 (...)'; the caller puts
    where in front ('joint 2 ').

    Args:
        values: {name: value} of one joint (every name of the pairs).
        given: {name: value as given}, shown with repr(); the others are shown as float32 text.
            A maximum given without its minimum is the one named (below). None: all of values.
        refused: names refused on their own already: their ranges are not checked.
    """
    given = values if given is None else given

    def shown(name):
        return repr(given[name]) if name in given else format_value(values[name])
    problems = []
    for low, high in RANGE_PAIRS:
        if low in refused or high in refused or values[low] <= values[high]:
            continue
        if high in given and low not in given:
            why = '%s = %s: below %s = %s' % (high, shown(high), low, format_value(values[low]))
        else:
            why = '%s = %s: above %s = %s' % (low, shown(low), high, format_value(values[high]))
        problems.append((low, high, why))
    for low, high in ZERO_RANGES:
        if (low in refused or high in refused or values[low] > values[high]
                or values[low] <= 0.0 <= values[high]):
            continue
        problems.append((low, high, "%s..%s = %s..%s: the range must hold 0 (the firmware's angle "
                         'filter would drift the angle)' % (low, high, format_value(values[low]),
                                                            format_value(values[high]))))
    return problems


def section(joint):
    """Return the ini section name of a joint, e.g. 'joint_3'."""
    return 'joint_%d' % joint


# Feel mode's gentle gains: the [feel] section of the arm's ini file. config_X lays them over the
# stored joint settings while <ns>/opmode is feel (robopuppet.config.feel_profile) and never
# stores the result in a joint's settings. Bounds: low < value <= high.
FEEL_SECTION = 'feel'
FeelSetting = collections.namedtuple('FeelSetting', 'name unit default meaning low high')
FEEL_SETTINGS = (
    FeelSetting('gain_scale', '', 0.25, 'pid_kp and pid_kd factor in feel mode (pid_ki is 0)',
                0.0, 1.0),
    FeelSetting('voltage_limit', 'V', 2.0, 'PID voltage bound in feel mode (+-)', 0.0,
                MOTOR_SUPPLY_V),   # more than the motors' supply would mean nothing
)
FEEL_NAMES = tuple(s.name for s in FEEL_SETTINGS)
FEEL_DEFAULTS = {s.name: s.default for s in FEEL_SETTINGS}
FEEL_BY_NAME = {s.name: s for s in FEEL_SETTINGS}
