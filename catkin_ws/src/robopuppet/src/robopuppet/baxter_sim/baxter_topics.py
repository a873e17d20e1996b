"""Baxter's topics as the stand-in serves them, as data: what it subscribes and publishes.

Pure: names (from interface.py) and message type names only.
"""
import collections

from robopuppet import interface
from robopuppet.baxter_sim import baxter_collision as collision, baxter_io as bio
from robopuppet.interface import BAXTER_SIDES

# The IO states published every cycle: (state topic of a name, message type, the names).
IO_STATES = (
    (interface.digital_io_state_topic, 'baxter_core_msgs/DigitalIOState',
     bio.DIGITAL_INPUTS + bio.DIGITAL_OUTPUTS),
    (interface.navigator_state_topic, 'baxter_core_msgs/NavigatorState', bio.NAVIGATORS),
    (interface.analog_io_state_topic, 'baxter_core_msgs/AnalogIOState',
     bio.ANALOG_INPUTS + bio.ANALOG_OUTPUTS),
)


def io_publications():
    """Return [(topic, message type)] of every IO and head state and each arm's collision
    avoidance state, published every cycle."""
    return ([(topic(name), kind) for topic, kind, names in IO_STATES for name in names]
            + [(interface.HEAD_STATE, 'baxter_core_msgs/HeadState')]
            + [(interface.collision_avoidance_state_topic(side),
                'baxter_core_msgs/CollisionAvoidanceState') for side in BAXTER_SIDES])


Subscription = collections.namedtuple('Subscription', 'topic kind method side fields timed')
Subscription.__doc__ = """A command topic: a `kind` message on `topic` runs BaxterApi.`method`
(topic, [side,] *the message's `fields` in order, [ROS time s when `timed`,] wall_s); `side` is
None for a topic of the whole robot."""


def subscriptions():
    """Return the Subscription of every command topic the stand-in obeys."""
    msgs = 'baxter_core_msgs/'
    rows = [Subscription(interface.SET_SUPER_ENABLE, 'std_msgs/Bool', 'set_enabled', None,
                         ('data',), False),
            Subscription(interface.SET_SUPER_RESET, 'std_msgs/Empty', 'reset', None, (), False),
            Subscription(interface.SET_SUPER_STOP, 'std_msgs/Empty', 'stop', None, (), False),
            Subscription(interface.DIGITAL_IO_COMMAND, msgs + 'DigitalOutputCommand',
                         'digital_output', None, ('name', 'value'), False),
            Subscription(interface.ANALOG_IO_COMMAND, msgs + 'AnalogOutputCommand',
                         'analog_output', None, ('name', 'value'), False),
            Subscription(interface.SIM_DIGITAL_INPUT, msgs + 'DigitalOutputCommand',
                         'digital_input', None, ('name', 'value'), False),
            Subscription(interface.HEAD_PAN_COMMAND, msgs + 'HeadPanCommand', 'head_pan', None,
                         ('target', 'speed_ratio', 'enable_pan_request'), False),
            Subscription(interface.HEAD_NOD_COMMAND, 'std_msgs/Bool', 'head_nod', None,
                         ('data',), False),
            Subscription(interface.JOINT_STATE_PUBLISH_RATE, 'std_msgs/UInt16', 'publish_rate',
                         None, ('data',), False)]
    for side in BAXTER_SIDES:
        limb = interface.limb_topic
        rows += [
            Subscription(limb(side, 'joint_command'), msgs + 'JointCommand', 'joint_command',
                         side, ('mode', 'names', 'command'), True),
            Subscription(limb(side, 'set_speed_ratio'), 'std_msgs/Float64', 'speed_ratio', side,
                         ('data',), False),
            Subscription(limb(side, 'joint_command_timeout'), 'std_msgs/Float64',
                         'command_timeout', side, ('data',), False),
            Subscription(interface.baxter_gripper_topic(side, 'command'),
                         msgs + 'EndEffectorCommand', 'gripper_command', side,
                         ('id', 'command', 'args', 'sender', 'sequence'), False),
            Subscription(limb(side, 'inverse_dynamics_command'),
                         'trajectory_msgs/JointTrajectoryPoint', 'inverse_dynamics', side,
                         ('positions', 'velocities', 'accelerations'), False)]
        rows += [Subscription(interface.baxter_gripper_topic(side, 'rsdk/set_' + what),
                              msgs + kind, 'custom_gripper', side, ('id',), False)
                 for what, kind in (('properties', 'EndEffectorProperties'),
                                    ('state', 'EndEffectorState'))]
        rows += [Subscription(interface.suppress_topic(side, behaviour), 'std_msgs/Empty',
                              'suppress_' + behaviour, side, (), True)
                 for behaviour in collision.BEHAVIOURS]
    return rows
