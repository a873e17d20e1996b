"""Tests of robopuppet.baxter_sim.baxter_statics against the URDF's own forward kinematics
(baxter_description.Description.transform, a separate code path): Jacobian, twist, wrench and
gravity torques."""
import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim import baxter_statics as st

RNG = np.random.default_rng(7)


def arm(side='left'):
    return st.ArmStatics(bd.load(), side), bd.arm_joint_names(side)


def random_q(side='left'):
    limits = bd.load().arm_limits(side)
    return np.array([RNG.uniform(lim.lower, lim.upper) for lim in limits])


def tool_pose(names, q, side='left'):
    return bd.load().transform(dict(zip(names, q)), bd.gripper_link(side))


def rotation_vector(r):
    """The axis x angle of a small rotation matrix r."""
    angle = np.arccos(np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0))
    axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    return axis / (2.0 * np.sin(angle)) * angle if angle > 1e-12 else axis / 2.0


def potential_energy(names, q, side='left'):
    """Sum of m g z over the arm's links, from the URDF's FK (not ArmStatics)."""
    description = bd.load()
    positions = dict(zip(names, q))
    energy = 0.0
    for link, (mass, com) in st.LINK_INERTIALS.items():
        pose = description.transform(positions, '%s_%s' % (side, link))
        energy += mass * st.GRAVITY_M_S2 * (pose @ np.append(com, 1.0))[2]
    return energy


@pytest.mark.parametrize('side', ['left', 'right'])
def test_the_tool_point_is_the_endpoint_pose_point(side):
    statics, names = arm(side)
    for _ in range(5):
        q = random_q(side)
        assert np.allclose(statics.frames(q)[3], tool_pose(names, q, side)[:3, 3], atol=1e-12)


@pytest.mark.parametrize('side', ['left', 'right'])
def test_the_twist_is_the_finite_difference_of_the_pose(side):
    statics, names = arm(side)
    dt = 1e-6
    for _ in range(20):
        q, qd = random_q(side), RNG.uniform(-1.5, 1.5, 7)
        twist = statics.endpoint(q, qd, np.zeros(7)).twist
        before, after = tool_pose(names, q - qd * dt, side), tool_pose(names, q + qd * dt, side)
        linear = (after[:3, 3] - before[:3, 3]) / (2 * dt)
        angular = rotation_vector(after[:3, :3] @ before[:3, :3].T) / (2 * dt)
        assert np.allclose(twist[:3], linear, atol=1e-6), (twist, linear)
        assert np.allclose(twist[3:], angular, atol=1e-6), (twist, angular)
        assert np.linalg.norm(twist) > 0.01   # a moving arm's tool point moves


def test_the_wrench_reproduces_the_efforts_through_the_jacobian():
    statics, _ = arm()
    for _ in range(20):
        q = random_q()
        jacobian = statics.jacobian(q)
        assert np.linalg.matrix_rank(jacobian) == 6
        wrench = RNG.uniform(-20.0, 20.0, 6)
        efforts = jacobian.T @ wrench
        found = statics.endpoint(q, np.zeros(7), efforts).wrench
        assert np.allclose(found, wrench, atol=1e-8)
        assert np.allclose(jacobian.T @ found, efforts, atol=1e-8)
    assert not statics.endpoint(random_q(), np.zeros(7), np.zeros(7)).wrench.any()


def test_a_push_at_the_tool_point_gives_the_efforts_of_that_force():
    # Virtual work: a force F at the tool point is held by efforts J^T F; a pure downward
    # press of 10 N on the gripper comes back as 10 N down and no torque.
    statics, _ = arm()
    q = np.array([bd.NEUTRAL_POSE[s] for s in bd.ARM_JOINT_SUFFIXES])
    press = np.array([0.0, 0.0, -10.0, 0.0, 0.0, 0.0])
    found = statics.endpoint(q, np.zeros(7), statics.jacobian(q).T @ press).wrench
    assert np.allclose(found, press, atol=1e-9)


def test_gravity_torques_are_the_gradient_of_the_potential_energy():
    statics, names = arm()
    assert statics.total_mass_kg == pytest.approx(20.05, abs=0.01)
    for _ in range(10):
        q = random_q()
        expected = [(potential_energy(names, q + step) - potential_energy(names, q - step)) / 2e-6
                    for step in np.eye(7) * 1e-6]
        assert np.allclose(statics.gravity(q), expected, atol=1e-4)


def test_a_joint_whose_load_hangs_straight_below_its_axis_holds_nothing():
    # Shoulder s1 horizontal, elbow e1 swings the forearm: where the forearm's centre of mass
    # (URDF FK) lies straight below e1's axis, e1 holds no torque; beside it, it does.
    statics, names = arm()
    description = bd.load()
    q = np.zeros(7)
    e1 = names.index('left_e1')

    def offset(angle):   # (sideways, vertical) offset of the mass beyond e1 from e1's axis
        q[e1] = angle
        positions = dict(zip(names, q))
        axis_pose = description.transform(positions, 'left_lower_elbow')
        moment, mass = np.zeros(3), 0.0
        for link in ('lower_elbow', 'upper_forearm', 'lower_forearm', 'wrist', 'hand',
                     'gripper_base'):
            m, com = st.LINK_INERTIALS[link]
            moment += m * (description.transform(positions, 'left_' + link)
                           @ np.append(com, 1.0))[:3]
            mass += m
        axis = axis_pose[:3, 2]
        assert abs(axis[2]) < 1e-9     # e1's axis is horizontal here
        sideways = np.cross(axis, [0.0, 0.0, 1.0])
        arm_m = moment / mass - axis_pose[:3, 3]
        return np.array([arm_m @ sideways, arm_m[2]])
    low, high = 0.5, 2.6
    assert np.sign(offset(low)[0]) != np.sign(offset(high)[0])
    for _ in range(60):
        middle = (low + high) / 2.0
        if np.sign(offset(middle)[0]) == np.sign(offset(low)[0]):
            low = middle
        else:
            high = middle
    below = offset(low)
    assert below[1] < -0.1 and abs(below[0]) < 1e-9
    assert abs(statics.gravity(q)[e1]) < 1e-6
    q[e1] -= 0.3
    assert abs(statics.gravity(q)[e1]) > 1.0


def test_a_horizontal_forearm_is_held_up_with_the_signs_of_lifting():
    # All joints 0: upper arm and forearm stretch out horizontally. Each horizontal-axis joint
    # holds with the sign of the motion that lifts the arm (positive where a positive turn
    # raises the centre of mass), and w1 near the hand holds far less than s1 at the shoulder.
    statics, names = arm()
    q = np.zeros(7)
    gravity = statics.gravity(q)
    for joint in ('left_s1', 'left_e1', 'left_w1'):
        i = names.index(joint)
        step = np.eye(7)[i] * 1e-3
        lift = potential_energy(names, q + step) - potential_energy(names, q)
        assert np.sign(gravity[i]) == np.sign(lift) != 0, joint
    s1, w1 = gravity[names.index('left_s1')], gravity[names.index('left_w1')]
    # s1 carries about 11 kg at about 0.5 m: of the order of 50 N m.
    assert 30.0 < abs(s1) < 80.0
    assert abs(w1) < 0.1 * abs(s1)
    assert abs(gravity[names.index('left_s0')]) < 1e-9    # a vertical axis holds no weight
