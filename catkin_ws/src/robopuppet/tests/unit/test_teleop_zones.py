"""Teleop with keep-out zones: a following arm is held at a zone's boundary, the detail names
zone and link, and it follows again when the puppet moves back out."""
import numpy as np

from robopuppet import baxter_description as bd, interface
from robopuppet.arm import teleop
from robopuppet.world import arm_capsules, shapes, zones

LIMITS = {side: bd.arm_limits(side) for side in interface.BAXTER_SIDES}
NEUTRAL = [bd.NEUTRAL_POSE[s] for s in bd.ARM_JOINT_SUFFIXES]
REACHING = [0.5, 0.3, 0.0, 0.9, 0.0, 0.4, 0.0]   # right gripper forward and down


def right_tip(angles):
    return np.array(bd.load().pose(dict(zip(bd.arm_joint_names('right'), angles)),
                                   'right_gripper')[0])


def rig():
    """Return (Teleop of puppet R following Baxter's right arm at neutral, its ZoneGuard): a
    ball zone sits where the puppet's reaching pose would put the gripper."""
    ball = shapes.parse_shape({'name': 'ball', 'type': 'sphere', 'radius': 0.08,
                               'xyz': list(right_tip(REACHING))})
    with open(bd.URDF_PATH) as urdf:
        capsules = arm_capsules.ArmCapsules(bd.load(), urdf.read(), 'right')
    guard = zones.ZoneGuard(capsules, [ball])
    assert guard.clearance(NEUTRAL).min() > 0.05
    tp = teleop.Teleop('R', LIMITS, zone_guards={'right': guard})
    return tp, guard


def run(tp, angles, t, steps):
    """Feed the puppet's angles and step at 100 Hz; return (t, the right arm's commands)."""
    commands, pose = [], NEUTRAL
    for _ in range(steps):
        t += 0.01
        tp.on_joint_states(t, [interface.WORKING] * 7, angles)
        tp.on_heartbeat(t)
        tp.on_robot(t, True)
        tp.on_robot_pose(t, {'left': NEUTRAL, 'right': pose})   # Baxter where commanded
        pose = tp.step(t).commands.get('right', pose)
        commands.append(pose)
    return t, commands


def test_a_following_arm_is_held_at_a_zone_and_follows_again_out_of_it():
    tp, guard = rig()
    t, _ = run(tp, NEUTRAL, 0.0, 2)
    tp.on_button(t, interface.BUTTON_RIGHT)
    t, _ = run(tp, NEUTRAL, t, 2)
    tp.on_button(t, 0)
    assert tp.following['right']
    t, commands = run(tp, REACHING, t, 400)   # 4 s: far longer than the approach needs
    assert all(guard.clearance(c).min() > 0.0 for c in commands)
    assert guard.clearance(commands[-1]).min() < zones.NEAR_M   # at the boundary ...
    assert np.linalg.norm(right_tip(commands[-1]) - right_tip(REACHING)) > 0.08   # ... not in
    assert tp.zone_hits['right'].zone == 'ball'
    assert (tp.zones.zone('left'), tp.zones.zone('right')) == ('', 'ball')
    assert tp.detail == "held back by keep-out zone 'ball' (%s)" % tp.zone_hits['right'].link
    assert tp.zone_hits['right'].link in ('right_gripper_base', 'r_gripper_l_finger',
                                          'r_gripper_r_finger', 'right_hand')
    t, commands = run(tp, NEUTRAL, t, 400)   # the puppet goes back
    assert all(guard.clearance(c).min() > 0.0 for c in commands)
    np.testing.assert_allclose(commands[-1], NEUTRAL, atol=1e-9)
    assert tp.zone_hits['right'] is None
    assert tp.zones.zone('right') == ''
    assert tp.detail == 'Baxter follows with its right arm'
