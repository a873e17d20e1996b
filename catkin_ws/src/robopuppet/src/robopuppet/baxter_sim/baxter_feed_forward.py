"""The check of an inverse_dynamics_command, the trajectory action server's feed-forward.

Rethink's joint trajectory action server (SDK 1.2.0, mode position_w_id) sends, beside its raw
position commands, a trajectory_msgs/JointTrajectoryPoint per control cycle on
/robot/limb/<side>/inverse_dynamics_command: 7 positions (rad) in the limb's joint order s0 ..
w2, and 7 velocities (rad/s) and accelerations (rad/s^2) or none, from which the robot's
inverse dynamics computes feed-forward torques for its joint controllers. The stand-in is
kinematic: its joints reach their position targets without torques, so a feed-forward has
nothing to act on. It is refused with a line saying why (or what is wrong with the point),
and the arm moves as its joint commands say. Pure: no ROS.
"""
import math

from robopuppet.baxter_sim.baxter_refusals import CommandError, brief

JOINTS = 7


def check_feed_forward(side, positions, velocities, accelerations):
    """Return the CommandError that refuses a feed-forward point: 'malformed feed-forward' for
    a point that is not 7 finite positions with 7 finite velocities and accelerations or none,
    else 'kinematic stand-in'."""
    for what, values, may_be_empty in (('positions', positions, False),
                                       ('velocities', velocities, True),
                                       ('accelerations', accelerations, True)):
        if len(values) != JOINTS and not (may_be_empty and not values):
            return CommandError('%s arm: inverse_dynamics_command has %d %s, not %d'
                                % (side, len(values), what, JOINTS), 'malformed feed-forward')
        if not all(math.isfinite(v) for v in values):
            return CommandError('%s arm: inverse_dynamics_command %s not finite: %s'
                                % (side, what, brief(list(values))), 'malformed feed-forward')
    return CommandError('%s arm: inverse_dynamics_command ignored: the stand-in is kinematic, '
                        'its joints track their position commands without feed-forward torques'
                        % side, 'kinematic stand-in')
