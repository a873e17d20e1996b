"""The puppet's joint settings (DESIGN section 5): one table, used by every node.

A setting's index in SETTINGS is its config id on the wire (serial frame 0x30) and its field
order in the GetConfig response.
"""
import collections

NUM_JOINTS = 7
JOINTS = tuple(range(NUM_JOINTS))
JOINT_NAMES = tuple('joint_%d' % j for j in JOINTS)  # sensor_msgs/JointState names

Setting = collections.namedtuple('Setting', 'name unit default meaning')

SETTINGS = (
    Setting('home_angle', 'rad', 0.0, 'angle zero offset'),
    Setting('angle_min', 'rad', -1.571, 'minimum angle'),
    Setting('angle_max', 'rad', 1.571, 'maximum angle'),
    Setting('velocity_min', 'rad/s', -6.283, 'minimum angular velocity'),
    Setting('velocity_max', 'rad/s', 6.283, 'maximum angular velocity'),
    Setting('voltage_min', 'V', -7.2, 'minimum PID voltage'),
    Setting('voltage_max', 'V', 7.2, 'maximum PID voltage'),
    Setting('pid_kp', 'V/rad', 0.0, 'P gain'),
    Setting('pid_ki', 'V/(rad*s)', 0.0, 'I gain'),
    Setting('pid_kd', 'V/(rad/s)', 0.0, 'D gain'),
    Setting('sign_angle', '+1/-1', 1.0, 'direction of angle'),
    Setting('sign_motor', '+1/-1', 1.0, 'direction of motor voltage'),
)

NAMES = tuple(s.name for s in SETTINGS)
CONFIG_ID = {s.name: index for index, s in enumerate(SETTINGS)}
DEFAULTS = {s.name: s.default for s in SETTINGS}

# (min, max) pairs: min must not exceed max.
RANGE_PAIRS = (('angle_min', 'angle_max'),
               ('velocity_min', 'velocity_max'),
               ('voltage_min', 'voltage_max'))
SIGNS = ('sign_angle', 'sign_motor')

# Encoder status strings of the ROS interface (DESIGN section 4), indexed by the wire code.
ENC_STATUS = ('Working', 'Disconnected', 'Uncalibrated')


def section(joint):
    """Return the ini section name of a joint, e.g. 'joint_3'."""
    return 'joint_%d' % joint


def namespace(side):
    """Return the ROS namespace of a puppet arm, e.g. '/puppet/arm_R'.

    Raises:
        ValueError: side is not 'L' or 'R'.
    """
    if side not in ('L', 'R'):
        raise ValueError("arm side must be 'L' or 'R', got %r" % (side,))
    return '/puppet/arm_%s' % side
