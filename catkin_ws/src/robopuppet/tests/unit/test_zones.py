"""Keep-out zones (robopuppet.world.zones): the swept arm never enters a zone, grazing is not cut.

The checks here do not use the guard's own geometry code: forward kinematics is chained from
baxter_description's joints (and compared with Description.transform), the arm's shapes are read
from the URDF's visuals here, and clearances are brute force: capsule segments sampled every
millimetre, motions sampled so that no arm point moves more than a millimetre or two between
samples, and each sample's exact signed distance to a box, sphere or cylinder.
"""
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.world import arm_capsules, shapes, zones

URDF_TEXT = open(bd.URDF_PATH).read()
DESCRIPTION = bd.Description(URDF_TEXT)
ZONES_FILE = bd.URDF_PATH.replace('urdf/baxter.urdf', 'config/zones.yaml')
SEGMENT_STEP_M = 0.001
MOTION_STEP_M = 0.002
REACH_M = 1.45       # farther than any arm point from any arm joint's axis (test's own figure)

# The shipped zones and a few more in the arms' way, in every shape the format has.
TEST_ZONES = zones.load_zones(ZONES_FILE) + [shapes.parse_shape(entry) for entry in (
    {'name': 'pole', 'type': 'cylinder', 'radius': 0.06, 'length': 0.9, 'xyz': [0.75, 0.3, 0.2],
     'rpy': [0.0, 0.3, 0.0]},
    {'name': 'lamp', 'type': 'sphere', 'radius': 0.12, 'xyz': [0.5, -0.75, 0.45]},
    {'name': 'tray', 'type': 'box', 'size': [0.4, 0.3, 0.05], 'xyz': [0.65, -0.35, 0.05],
     'rpy': [0.2, -0.1, 0.7]},
    {'name': 'drip stand', 'type': 'cylinder', 'radius': 0.04, 'length': 1.4,
     'xyz': [0.2, 0.95, 0.0], 'rpy': [0.0, 0.0, 0.0]},
)]


# ---- the test's own model of the arm -------------------------------------------------------

def _turn(axis, angles):
    x, y, z = axis
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    s, c = np.sin(angles)[:, None, None], np.cos(angles)[:, None, None]
    out = np.tile(np.eye(4), (len(angles), 1, 1))
    out[:, :3, :3] = np.eye(3) + s * k + (1.0 - c) * (k @ k)
    return out


def link_poses(side, q, opening):
    """Return {link below the arm mount: (M, 4, 4) pose in base} for (M, 7) angles and a
    gripper finger travel (m, 0 closed .. 0.020833 open)."""
    names = bd.arm_joint_names(side)
    mount = '%s_arm_mount' % side
    poses = {mount: np.tile(DESCRIPTION.transform({}, mount), (len(q), 1, 1))}
    pending = list(DESCRIPTION.joints.values())
    while pending:
        for joint in [j for j in pending if j.parent in poses]:
            step = np.tile(joint.origin, (len(q), 1, 1))
            if joint.type == 'revolute':
                step = step @ _turn(joint.axis, q[:, names.index(joint.name)])
            elif joint.type == 'prismatic':
                move = np.eye(4)
                move[:3, 3] = joint.axis * opening * (joint.mimic[1] if joint.mimic else 1.0)
                step = step @ move
            poses[joint.child] = poses[joint.parent] @ step
        left = [j for j in pending if j.child not in poses]
        if len(left) == len(pending):
            break
        pending = left
    poses.pop(mount)
    return poses


def visual_capsules(side, grow_fingers=False):
    """Return [(link, end 1, end 2, radius)] in link frames from the URDF's visuals: a cylinder
    is its axis, a box its longest side with the half diagonal of the others; fingers grown by
    half their travel when asked (the guard's model for any opening)."""
    links = set(link_poses(side, np.zeros((1, 7)), 0.0))
    out = []
    for link in ET.fromstring(URDF_TEXT).findall('link'):
        if link.get('name') not in links:
            continue
        for visual in link.findall('visual'):
            origin = visual.find('origin')
            pose = np.eye(4)
            pose[:3, :3] = bd.rpy_matrix(*map(float, origin.get('rpy').split()))
            pose[:3, 3] = list(map(float, origin.get('xyz').split()))
            shape = visual.find('geometry')[0]
            if shape.tag == 'cylinder':
                half = pose[:3, 2] * float(shape.get('length')) / 2.0
                radius = float(shape.get('radius'))
            elif shape.tag == 'box':
                size = np.array(list(map(float, shape.get('size').split())))
                k = int(np.argmax(size))
                half = pose[:3, k] * size[k] / 2.0
                radius = np.linalg.norm(np.delete(size, k)) / 2.0
            else:
                half, radius = np.zeros(3), float(shape.get('radius'))
            if grow_fingers and 'finger' in link.get('name'):
                radius += 0.020833 / 2.0
            out.append((link.get('name'), pose[:3, 3] - half, pose[:3, 3] + half, radius))
    return out


def signed_distance(shape, points):
    """Return the exact signed distance (m) of (..., 3) base-frame points to a Shape."""
    pose = shapes.shape_pose(shape)
    local = (points - pose[:3, 3]) @ pose[:3, :3]
    if shape.type == 'sphere':
        return np.linalg.norm(local, axis=-1) - shape.radius
    if shape.type == 'capsule':   # a cylinder's axis grown by its radius, ends rounded
        axial = np.clip(local[..., 2], -shape.length / 2.0, shape.length / 2.0)
        return np.linalg.norm(local - np.stack([0.0 * axial, 0.0 * axial, axial], axis=-1),
                              axis=-1) - shape.radius
    if shape.type == 'box':
        excess = np.abs(local) - np.array(shape.size) / 2.0
    else:
        excess = np.stack([np.linalg.norm(local[..., :2], axis=-1) - shape.radius,
                           np.abs(local[..., 2]) - shape.length / 2.0], axis=-1)
    return np.linalg.norm(np.maximum(excess, 0.0), axis=-1) + \
        np.minimum(excess.max(axis=-1), 0.0)


class BruteForce:
    """Clearances of an arm's capsules from shapes, by sampling segments and motions.

    A capsule whose middle is farther from the shape than half its length plus its radius plus
    NEAR_M is clear by at least that much; the others are sampled every COARSE_M, and those
    that this does not prove clear by 2 NEAR_M (the sampled distance less COARSE_M / 2) every
    SEGMENT_STEP_M.
    """

    NEAR_M = 0.01
    COARSE_M = 0.01   # first every this (a lower bound: the distance is 1-Lipschitz along it)

    def __init__(self, side, grow_fingers=False):
        self.side = side
        capsules = visual_capsules(side, grow_fingers)
        self.links = [c[0] for c in capsules]
        self.ends = np.array([[np.append(c[1], 1.0), np.append(c[2], 1.0)] for c in capsules])
        self.radii = np.array([c[3] for c in capsules])
        self.opening = 0.020833 / 2.0 if grow_fingers else None
        longest = np.linalg.norm(self.ends[:, 1] - self.ends[:, 0], axis=1).max()
        self.t = np.linspace(0.0, 1.0, int(np.ceil(longest / SEGMENT_STEP_M)) + 1)
        self.coarse_t = np.linspace(0.0, 1.0, int(np.ceil(longest / self.COARSE_M)) + 1)

    def clearances(self, q, zone_list, opening=0.0):
        """Return (Z, C) least clearances (m) over configurations (M, 7) from each shape."""
        return np.array([gap.min(axis=0) for gap in self.gaps(q, zone_list, opening)])

    def least(self, q, zone_list, opening=0.0):
        """Return (M,) each configuration's least clearance (m) from any of the shapes."""
        return np.min([gap.min(axis=1) for gap in self.gaps(q, zone_list, opening)], axis=0)

    def gaps(self, q, zone_list, opening=0.0):
        """Return per shape the (M, C) clearances (m) of configurations (M, 7)."""
        poses = link_poses(self.side, np.atleast_2d(q), self.opening or opening)
        frames = np.stack([poses[link][:, :3, :] for link in self.links], axis=1)  # (M,C,3,4)
        ends = np.einsum('mcij,cej->mcei', frames, self.ends)                     # (M,C,2,3)
        middle = ends.mean(axis=2)
        half = np.linalg.norm(ends[:, :, 1] - ends[:, :, 0], axis=-1) / 2.0
        result = []
        for shape in zone_list:
            gap = signed_distance(shape, middle) - half - self.radii
            for t, step_m in ((self.coarse_t, self.COARSE_M), (self.t, 0.0)):
                m, c = np.nonzero(gap < self.NEAR_M + (self.COARSE_M if step_m else 0.0))
                if len(m):
                    a, b = ends[m, c, 0], ends[m, c, 1]
                    points = a[:, None] + t[None, :, None] * (b - a)[:, None]
                    gap[m, c] = (signed_distance(shape, points).min(axis=1) - self.radii[c]
                                 - step_m / 2.0)
            result.append(gap)
        return result

    def clearance(self, q, shape, opening=0.0):
        """Return {link: least clearance (m)} over configurations (M, 7) from one shape."""
        least = self.clearances(q, [shape], opening)[0]
        return {link: least[[i for i, n in enumerate(self.links) if n == link]].min()
                for link in set(self.links)}

    def path(self, q_from, q_to):
        """Return the configurations (M, 7) sampling a straight motion finely."""
        reach = REACH_M * np.abs(np.subtract(q_to, q_from)).sum()
        s = np.linspace(0.0, 1.0, int(np.ceil(reach / MOTION_STEP_M)) + 1)[:, None]
        return q_from + s * (np.subtract(q_to, q_from))

    def sweep(self, q_from, q_to, shape, opening=0.0):
        """Return {link: least clearance} over the straight motion, finely sampled."""
        return self.clearance(self.path(q_from, q_to), shape, opening)


def guard(side, zone_list=TEST_ZONES):
    return zones.ZoneGuard(arm_capsules.ArmCapsules(DESCRIPTION, URDF_TEXT, side), zone_list)


def limits(side):
    lims = DESCRIPTION.arm_limits(side)
    return np.array([x.lower for x in lims]), np.array([x.upper for x in lims])


# ---- the tests ---------------------------------------------------------------------------

def test_the_test_kinematics_are_the_urdf_s():
    rng = np.random.default_rng(3)
    q = rng.uniform(*limits('left'), size=(5, 7))
    poses = link_poses('left', q, 0.01)
    for m in range(5):
        positions = dict(zip(bd.arm_joint_names('left'), q[m]))
        positions['l_gripper_l_finger_joint'] = 0.01
        for link in ('left_lower_elbow', 'left_gripper', 'l_gripper_r_finger'):
            np.testing.assert_allclose(poses[link][m], DESCRIPTION.transform(positions, link),
                                       atol=1e-12)


@pytest.mark.parametrize('side', bd.BAXTER_SIDES if hasattr(bd, 'BAXTER_SIDES')
                         else ('left', 'right'))
def test_the_capsules_hold_every_visual_shape_from_shoulder_to_fingertips(side):
    capsules = arm_capsules.ArmCapsules(DESCRIPTION, URDF_TEXT, side)
    links = set(link_poses(side, np.zeros((1, 7)), 0.0))
    assert set(capsules.links) == {c[0] for c in visual_capsules(side)}
    assert {'%s_upper_shoulder' % side, '%s_gripper_base' % side} <= set(capsules.links)
    assert set(capsules.links) <= links
    rng = np.random.default_rng(4)
    for _ in range(20):
        q = rng.uniform(*limits(side), size=(1, 7))
        opening = rng.uniform(0.0, 0.020833)
        poses = link_poses(side, q, opening)
        segments = capsules.segments(q)[0]                       # (C, 3, 2)
        for link, end_1, end_2, radius in visual_capsules(side):
            # The corners and ends of the shape: points of the URDF's own solid.
            ends = np.array([end_1, end_2])
            axis = (end_2 - end_1) / max(np.linalg.norm(end_2 - end_1), 1e-12)
            side_dir = np.cross(axis, [1.0, 0.0, 0.0])
            if np.linalg.norm(side_dir) < 0.1:
                side_dir = np.cross(axis, [0.0, 1.0, 0.0])
            side_dir *= radius / np.linalg.norm(side_dir) * 0.999
            local = np.concatenate([ends + side_dir, ends - side_dir])
            points = local @ poses[link][0, :3, :3].T + poses[link][0, :3, 3]
            mine = [c for c, name in enumerate(capsules.links) if name == link]
            for point in points:
                gaps = []
                for c in mine:
                    a, b = segments[c, :, 0], segments[c, :, 1]
                    t = np.clip(np.dot(point - a, b - a) / max(np.dot(b - a, b - a), 1e-24),
                                0.0, 1.0)
                    gaps.append(np.linalg.norm(point - (a + t * (b - a))) - capsules.radii[c])
                assert min(gaps) <= 1e-9, (link, point)


def _random_motions(side, rng, count, scale, near_m):
    """Return [(q_from, q_to, finger opening)]: q_from outside every zone and, for most, within
    near_m of one; q_to a random motion of up to `scale` rad per joint from it."""
    lower, upper = limits(side)
    brute = BruteForce(side)
    motions = []
    while len(motions) < count:
        q = rng.uniform(lower, upper, size=(200, 7))
        opening = rng.uniform(0.0, 0.020833)
        least = brute.least(q, TEST_ZONES, opening)
        chosen = q[(least > 0.0) & (least < near_m)]
        motions += [(x, np.clip(x + rng.uniform(-1.0, 1.0, 7) * scale, lower, upper), opening)
                    for x in chosen[:count - len(motions)]]
    return motions


@pytest.mark.slow
@pytest.mark.parametrize('side, seed', [('left', 11), ('right', 12)])
def test_no_returned_command_sweeps_the_arm_into_a_zone(side, seed):
    """5,000 motions per arm (10,000 in all): 4,500 of teleop size near zones, 500 large."""
    rng = np.random.default_rng(seed)
    checker, brute = guard(side), BruteForce(side)
    by_name = {z.name: z for z in TEST_ZONES}
    cut = stuck = 0
    for n, (q_from, q_to, opening) in enumerate(
            _random_motions(side, rng, 4500, np.array([0.03] * 4 + [0.08] * 3), 0.08) +
            _random_motions(side, rng, 500, 0.6, np.inf)):
        q_out, hit = checker.limit(q_from, q_to)
        motion = q_to - q_from
        share = np.dot(np.subtract(q_out, q_from), motion) / max(np.dot(motion, motion), 1e-30)
        np.testing.assert_allclose(q_out, q_from + share * motion, atol=1e-9)  # on the motion
        assert -1e-12 <= share <= 1.0 + 1e-12
        if hit is None:
            assert list(q_out) == list(q_to)
        else:
            cut += 1
            stuck += share == 0.0
            wall = by_name[hit.zone]
            if wall.type == 'cylinder':   # the guard keeps out of the capsule around its axis
                wall = wall._replace(type='capsule')
            at_stop = brute.clearance(q_out, wall, opening)
            # The pair is at the wall: within the fingers' travel (the guard's finger capsules
            # hold them at any opening) and a millimetre.
            assert at_stop[hit.link] < 2 * 0.020833 / 2.0 + 0.002, (hit, at_stop[hit.link])
        worst = brute.clearances(brute.path(q_from, q_out), TEST_ZONES, opening).min()
        assert worst > 0.0, (n, worst, q_from, q_to, q_out)
    assert cut > 150 and stuck < cut  # the zones were in the way, and cuts kept some motion


@pytest.mark.slow
def test_sliding_from_the_boundary_never_sweeps_the_arm_into_a_zone():
    """From each arm held by a cut (of 3,000 motions near a zone), slide toward a new target."""
    side, rng = 'left', np.random.default_rng(13)
    checker, brute = guard(side), BruteForce(side)
    lower, upper = limits(side)
    moved = 0
    for q_from, q_to, opening in _random_motions(side, rng, 3000, np.array([0.03] * 4 +
                                                                           [0.08] * 3), 0.03):
        held, hit = checker.limit(q_from, q_to)
        if hit is None:
            continue
        target = np.clip(held + rng.uniform(-1.0, 1.0, 7) * np.array([0.03] * 4 + [0.08] * 3),
                         lower, upper)
        q_out, _ = checker.slide(held, target)
        moved += not np.array_equal(q_out, held)
        worst = brute.clearances(brute.path(held, q_out), TEST_ZONES, opening).min()
        assert worst > 0.0, (worst, held, target, q_out)
    assert moved > 100


def _grazing_cases(side, rng, wanted):
    """Yield (q_from, q_to, zone) where the guard's own capsule model clears the zone along the
    whole motion by 4.5 to 9 mm (brute force; the guard stops 2 to 3 mm out), the zone grown
    from a shipped or test zone."""
    lower, upper = limits(side)
    brute = BruteForce(side, grow_fingers=True)
    found = 0
    for _ in range(20 * wanted):
        zone = TEST_ZONES[rng.integers(len(TEST_ZONES))]
        if zone.type == 'cylinder':
            continue   # the guard's cylinder distance is a lower bound near rims
        q_from = rng.uniform(lower, upper)
        q_to = np.clip(q_from + rng.uniform(-1.0, 1.0, 7) * 0.08, lower, upper)
        gap = min(brute.sweep(q_from, q_to, zone).values())
        if not 0.01 < gap < 0.5:
            continue
        for _ in range(12):   # a box grown by g on every side comes g .. g sqrt(3) nearer
            grow = gap - 0.0065
            if zone.type == 'sphere':
                zone = zone._replace(radius=zone.radius + grow)
            else:
                zone = zone._replace(size=tuple(s + 2.0 * grow / np.sqrt(3.0)
                                                for s in zone.size))
            gap = min(brute.sweep(q_from, q_to, zone).values())
            if gap <= 0.009:
                break
        if 0.0045 <= gap <= 0.009:
            found += 1
            yield q_from, q_to, zone
            if found == wanted:
                return
    assert found == wanted


@pytest.mark.parametrize('side, seed', [('left', 21), ('right', 22)])
def test_a_motion_that_grazes_a_zone_is_not_cut(side, seed):
    rng = np.random.default_rng(seed)
    for q_from, q_to, zone in _grazing_cases(side, rng, 40):
        q_out, hit = guard(side, [zone]).limit(q_from, q_to)
        assert hit is None and list(q_out) == list(q_to), (zone, hit)


def _pose_above_head(side):
    """Return angles that put the left gripper 12 cm above the patient-head zone's top, and
    angles that drive it down through the zone (found by a coarse search on the test's FK)."""
    rng = np.random.default_rng(5)
    lower, upper = limits(side)
    q = rng.uniform(lower, upper, size=(40000, 7))
    tips = link_poses(side, q, 0.0)['%s_gripper' % side][:, :3, 3]
    down = link_poses(side, q, 0.0)['%s_gripper' % side][:, :3, 2]
    target = np.array([0.85, 0.80, -0.10 + 0.18 + 0.12])
    score = np.linalg.norm(tips - target, axis=1) + 0.3 * (1.0 + down[:, 2])
    return q[np.argmin(score)]


def _moving_tip(side, q, move):
    """Return the joint motion that moves the gripper's tip by `move` (m), to first order."""
    tip = link_poses(side, q + np.vstack([np.zeros(7), 1e-6 * np.eye(7)]), 0.0)[
        '%s_gripper' % side][:, :3, 3]
    jacobian = (tip[1:] - tip[0]).T / 1e-6
    return np.linalg.pinv(jacobian) @ np.asarray(move)


def test_a_gripper_driven_into_the_patient_s_head_stops_at_the_zone_naming_it():
    side = 'left'
    q_from = _pose_above_head(side)
    tip = link_poses(side, q_from[None], 0.0)['left_gripper'][0, :3, 3]
    assert tip[2] > 0.15 and np.linalg.norm(tip[:2] - (0.85, 0.80)) < 0.15
    lower, upper = limits(side)
    q_to = np.clip(q_from + _moving_tip(side, q_from, (0.0, 0.0, -0.3)), lower, upper)
    head = zones.load_zones(ZONES_FILE)[0]
    brute = BruteForce(side)
    assert min(brute.clearance(q_to, head).values()) < 0.0   # the target is inside the zone
    q_out, hit = guard(side, zones.load_zones(ZONES_FILE)).limit(q_from, q_to)
    assert hit.zone == 'patient head'
    assert hit.link in ('left_gripper_base', 'l_gripper_l_finger', 'l_gripper_r_finger',
                        'left_hand', 'left_hand_camera')
    stop = BruteForce(side, grow_fingers=True).clearance(q_out, head)
    assert zones.MARGIN_M < stop[hit.link] < zones.NEAR_M   # held a few millimetres out
    assert min(stop.values()) == pytest.approx(stop[hit.link])


def test_from_inside_a_zone_only_motions_that_do_not_go_deeper_pass():
    side = 'left'
    q_from = _pose_above_head(side)
    tip = link_poses(side, q_from[None], 0.0)['left_gripper'][0, :3, 3]
    # A zone file changed: the gripper is now 3 cm inside a new box.
    box = shapes.parse_shape({'name': 'new box', 'type': 'box', 'size': [0.4, 0.4, 0.4],
                              'xyz': list(tip - (0.0, 0.0, 0.17))})
    checker = guard(side, [box])
    assert checker.clearance(q_from).min() < 0.0
    lower, upper = limits(side)
    deeper = np.clip(q_from + [0.0, 0.05, 0.0, 0.0, 0.0, 0.0, 0.0], lower, upper)
    out = np.clip(q_from + [0.0, -0.05, 0.0, 0.0, 0.0, 0.0, 0.0], lower, upper)
    assert checker.clearance(deeper).min() < checker.clearance(q_from).min()
    assert checker.clearance(out).min() > checker.clearance(q_from).min()
    q_out, hit = checker.limit(q_from, deeper)
    assert list(q_out) == list(q_from) and hit.zone == 'new box'
    q_out, hit = checker.limit(q_from, out)
    assert list(q_out) == list(out) and hit is None
    assert checker.limit(q_from, q_from) == (list(q_from), None)   # staying is allowed
    q_out, hit = checker.limit_box(q_from, q_from, q_from, deeper)   # the same for a box
    assert list(q_out) == list(q_from) and hit.zone == 'new box'
    q_out, _ = checker.limit_box(q_from, q_from, q_from, out)
    assert checker.clearance(q_out).min() > checker.clearance(q_from).min()


def test_without_zones_every_command_passes():
    checker = guard('right', [])
    assert checker.limit([0.0] * 7, [1.0] * 7) == ([1.0] * 7, None)


# ---- the box of Baxter's motion (limit_box) --------------------------------------------------

def _box_samples(rng, lo, hi, count):
    """Return (128 + count, 7) configurations of the box lo..hi: every corner, then random."""
    corners = np.array(np.meshgrid(*zip(lo, hi), indexing='ij')).reshape(7, -1).T
    return np.vstack([corners, rng.uniform(lo, hi, size=(count, 7))])


@pytest.mark.slow
@pytest.mark.parametrize('side, seed', [('left', 31), ('right', 32)])
def test_a_returned_command_keeps_the_whole_box_of_the_lagging_arm_out_of_the_zones(side, seed):
    """1,000 commands per arm near zones, Baxter anywhere up to 0.1 rad per joint behind the
    last command: the box between where it can be and the returned command, sampled at its
    128 corners and 64 random points, is outside every zone (brute force)."""
    rng = np.random.default_rng(seed)
    checker, brute = guard(side), BruteForce(side)
    lower, upper = limits(side)
    passed = held = moved = 0
    for q_from, q_to, opening in _random_motions(side, rng, 1000, np.array([0.03] * 4 +
                                                                           [0.08] * 3), 0.08):
        behind = np.clip(q_from - rng.uniform(-1.0, 1.0, 7) * rng.uniform(0.0, 0.1),
                         lower, upper)
        if brute.least(behind[None], TEST_ZONES, opening)[0] <= zones.NEAR_M:
            continue   # Baxter itself must have been outside the zones
        lo, hi = np.minimum(behind, q_from), np.maximum(behind, q_from)
        q_out, hit = checker.limit_box(lo, hi, q_from, q_to)
        if hit is None:
            passed += 1
            assert list(q_out) == list(q_to)
        else:
            held += 1
            moved += list(q_out) != list(q_from)
            assert hit.zone in checker.names and hit.link in checker.capsules.links
        if list(q_out) == list(q_from):
            continue   # the same target as before: proven when it was sent
        box = _box_samples(rng, np.minimum(lo, q_out), np.maximum(hi, q_out), 64)
        worst = brute.least(box, TEST_ZONES, opening).min()
        assert worst > 0.0, (worst, behind, q_from, q_to, q_out)
    assert passed > 100 and held > 100 and moved > 20   # all three cases were met


def test_a_lagging_arm_near_a_zone_waits_where_the_commands_alone_would_pass():
    side = 'left'
    q_from = _pose_above_head(side)
    head = zones.load_zones(ZONES_FILE)[:1]
    checker = guard(side, head)
    lower, upper = limits(side)
    toward = _moving_tip(side, q_from, (0.0, 0.0, -0.1))   # gripper 10 cm down, to 2 cm above
    q_to = np.clip(q_from + 0.01 * toward / np.abs(toward).max(), lower, upper)
    assert checker.limit(q_from, q_to) == (list(q_to), None)   # the commands' own motion: clear
    behind = np.clip(q_from - 0.25 * toward / np.abs(toward).max(), lower, upper)
    box = np.minimum(behind, q_from), np.maximum(behind, q_from)
    q_out, hit = checker.limit_box(*box, q_from, q_to)
    assert hit.zone == 'patient head' and list(q_out) != list(q_to)   # lagging: it waits
    q_out, hit = checker.limit_box(q_from, q_from, q_from, q_to)      # caught up: it goes
    assert (q_out, hit) == (list(q_to), None)


def _tangent_wall(side, q_from, q_to):
    """Return a box zone that a turn of joint 0 from q_from to q_to passes at its middle: its
    face is perpendicular to the direction, from joint 0's axis, of the arm's outermost capsule
    point there, and the arm's least clearance from it at q_from is 0.5 mm."""
    q_mid = (np.asarray(q_from) + q_to) / 2.0
    arm = guard(side, []).capsules
    ends = arm.segments([q_mid])[0]                               # (C, 3, 2)
    mount = DESCRIPTION.transform({}, '%s_arm_mount' % side)[:3, 3]
    radial = ends - mount[:, None]
    radial[:, 2] = 0.0                                            # joint 0 turns about z
    outer = np.linalg.norm(radial, axis=1) + arm.radii[:, None]   # (C, 2)
    c, e = np.unravel_index(np.argmax(outer), outer.shape)
    normal = radial[c, :, e] / np.linalg.norm(radial[c, :, e])
    wall = shapes.parse_shape({'name': 'wall', 'type': 'box', 'size': [0.3, 0.3, 0.3],
                               'xyz': list(ends[c, :, e] + normal * 0.2),
                               'rpy': [0.0, 0.0, float(np.arctan2(normal[1], normal[0]))]})
    gap = guard(side, [wall]).clearance(q_from).min()
    return wall._replace(xyz=tuple(np.add(wall.xyz, -normal * (gap - 0.0005))))


def test_a_motion_from_just_outside_a_zone_never_dips_into_it():
    """The arm 0.5 mm outside a wall (nearer than the margin) turns joint 0 along it: the tip's
    arc bulges 0.3 mm into the wall and ends farther out than it started. Each guard keeps it
    out (the floor of a pair near a zone may lie below its start, never below 0)."""
    side, alpha = 'left', 0.03
    q_mid = _pose_above_head(side)
    q_from = q_mid - np.eye(7)[0] * alpha
    checker = guard(side, [_tangent_wall(side, q_from, q_mid + np.eye(7)[0] * alpha)])
    path = lambda a, b: a + np.linspace(0.0, 1.0, 400)[:, None] * np.subtract(b, a)
    turns = path(q_from, q_from + np.eye(7)[0] * 4 * alpha)
    gaps = np.array([checker.clearance(q).min() for q in turns])
    deepest = int(np.argmin(gaps))
    q_to = turns[deepest + np.argmax(gaps[deepest:] > gaps[0] + 0.0001)]   # out again
    assert 0.0 < gaps[0] < zones.SLACK_M and -zones.SLACK_M / 2 < gaps.min() < -0.0002
    for q_out, _ in (checker.limit(q_from, q_to), checker.limit_box(q_from, q_from, q_from,
                                                                   q_to)):
        assert min(checker.clearance(q).min() for q in path(q_from, q_out)) >= 0.0


def test_the_floor_keeps_a_pair_out_of_a_zone_it_starts_outside():
    start = np.array([[0.05, zones.NEAR_M + 1e-6, zones.NEAR_M - 1e-6, zones.SLACK_M / 2,
                       1e-9, 0.0, -0.003]])
    near, floor = zones.floors(start)
    assert near.tolist() == [[False, False, True, True, True, True, True]]
    np.testing.assert_allclose(floor, [[zones.MARGIN_M, zones.MARGIN_M,
                                        zones.NEAR_M - 1e-6 - zones.SLACK_M,
                                        0.0, 0.0,                  # never into it from outside
                                        -zones.SLACK_M, -0.003 - zones.SLACK_M]])
