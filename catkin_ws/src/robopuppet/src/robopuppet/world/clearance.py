"""How far capsules (segment + radius) are from shapes (boxes, spheres, cylinders), vectorised.

A clearance is signed: the distance between a capsule and a shape when they are apart, at most 0
when they touch or overlap (then minus how deep the deepest point of the capsule's segment lies
in the shape, less the capsule's radius). Exact for boxes and spheres. For a cylinder, a lower
bound: the larger of the clearances from the capsule around its axis (its radius, rounded ends)
and from the slab between its cap planes; exact beside its side and over its caps, it can be
short by up to the cylinder's radius near a rim (a cylinder zone may stop the arm that much
early there). Every clearance here (and the quicker bound used for pairs far apart) moves by at
most d when no point of the segment moves more than d, which is what makes a check between
sampled configurations sound (world.zones).

Pure numpy, no ROS. The code works on arrays with the x, y, z components first and keeps the
number of numpy calls low: with a few dozen capsules, per-call overhead is the cost.
"""
import numpy as np

from robopuppet.world import shapes as shape_files

TOUCH_M = 1e-9  # below this a segment is taken to reach the box (and is measured inside)


def segment_box(a, d, h):
    """Return the least signed distance (m) from a point of each segment to a centred box.

    Args:
        a: (3, N) segment starts in the box's frame; d: (3, N) from start to end.
        h: (3, N) the box's half sizes (0 along an axis: a flat box, a line or a point).
    Returns:
        (N,) the distance between segment and box when they are apart, else the signed
        distance (negative inside) of the segment's deepest point.
    """
    n = a.shape[1]
    # The squared distance along the segment is convex, piecewise quadratic between the
    # crossings of the face planes; its slope is piecewise linear and rises, so its zero lies
    # between the last crossing (or end) where the slope is <= 0 and the first where >= 0.
    step = np.where(d != 0.0, d, np.inf)    # a segment parallel to a face never crosses it: 0
    t = np.empty((8, n))
    t[:3], t[3:6], t[6], t[7] = (h - a) / step, (-h - a) / step, 0.0, 1.0
    np.minimum(np.maximum(t, 0.0, out=t), 1.0, out=t)
    point = a[:, None] + t * d[:, None]                                          # (3, 8, N)
    slope = (d[:, None] * (point - np.minimum(np.maximum(point, -h[:, None]), h[:, None]))
             ).sum(axis=0)                      # half the squared distance's slope, (8, N)
    down, up = slope <= 0.0, slope >= 0.0
    low, high = np.where(down, t, 0.0).max(axis=0), np.where(up, t, 1.0).min(axis=0)
    slope_low = np.where(down, slope, -np.inf).max(axis=0)
    slope_high = np.where(up, slope, np.inf).min(axis=0)
    # Where the slope is 0, linearly between them. No slope <= 0: the start is nearest (the
    # span is infinite: 0); none >= 0: the end; both 0: anywhere between (0).
    span = slope_high - slope_low
    share = np.divide(-slope_low, span, out=np.zeros(n), where=(span > 0.0) & (span < np.inf))
    share[slope_high == np.inf] = 1.0
    point = a + (low + share * (high - low)) * d
    outside = point - np.minimum(np.maximum(point, -h), h)
    gap = np.sqrt((outside * outside).sum(axis=0))
    touching = gap <= TOUCH_M   # rounding leaves about 1e-16 where segment and box meet
    if touching.any():
        gap[touching] = np.minimum(gap[touching], _deepest(a[:, touching], d[:, touching],
                                                           h[:, touching]))
    return gap


def segment_point(a, d):
    """Return the distance (m) from the origin to each segment, a (3, N) starts, d (3, N) from
    start to end: segment_box for a box of size 0 (a sphere's centre), in fewer steps."""
    length2 = (d * d).sum(axis=0)
    t = np.divide(-(a * d).sum(axis=0), length2, out=np.zeros(a.shape[1]), where=length2 > 0.0)
    point = a + np.minimum(np.maximum(t, 0.0), 1.0) * d
    return np.sqrt((point * point).sum(axis=0))


def _deepest(a, d, h):
    """Return the least signed distance inside a box along segments that reach into it: the
    minimum over t of max_k(|p_k(t)| - h_k), at an end or where two of its lines cross."""
    slopes, offsets = np.concatenate([d, -d]), np.concatenate([a - h, -a - h])   # (6, N)
    rise = slopes[None, :] - slopes[:, None]
    n = a.shape[1]
    t = np.zeros((38, n))   # the ends, then where two lines cross (parallel ones: an end)
    t[1] = 1.0
    np.divide(offsets[:, None] - offsets[None, :], rise, out=t[2:].reshape(6, 6, n),
              where=rise != 0.0)
    np.minimum(np.maximum(t, 0.0, out=t), 1.0, out=t)
    points = a[:, None] + t[None] * d[:, None]                                   # (3, 38, N)
    return np.min(np.max(np.abs(points) - h[:, None], axis=0), axis=0)


class ShapeSet:
    """Shapes (world.shapes.Shape: box, sphere, cylinder) to measure capsules against.

    A box is its own box; a sphere is a point grown by its radius; a cylinder is its axis
    segment grown by its radius (a capsule, which holds it) and also its slab between the cap
    planes: the clearance is the larger of the two, both lower bounds.
    """

    def __init__(self, shapes):
        self.shapes = list(shapes)
        self.names = [s.name for s in self.shapes]
        count = len(self.shapes)
        self._rotation = np.zeros((count, 3, 3))   # base -> shape frame
        self._offset = np.zeros((count, 3, 1))     # the shape's centre in its own frame's axes
        self._half = np.zeros((count, 3, 1))
        self._grow = np.zeros((count, 1, 1))
        self._slab = np.zeros(count)
        for i, shape in enumerate(self.shapes):
            pose = shape_files.shape_pose(shape)
            self._rotation[i] = pose[:3, :3].T
            self._offset[i, :, 0] = pose[:3, :3].T @ pose[:3, 3]
            if shape.type == 'box':
                self._half[i, :, 0] = np.array(shape.size) / 2.0
            elif shape.type == 'sphere':
                self._grow[i] = shape.radius
            else:
                self._half[i, 2] = self._slab[i] = shape.length / 2.0
                self._grow[i] = shape.radius
        self._is_cylinder = np.array([s.type == 'cylinder' for s in self.shapes])
        self._is_point = np.array([s.type == 'sphere' for s in self.shapes])
        self._half_rotation = self._rotation / 2.0   # takes a capsule's two ends' sum

    def clearance(self, segments, half_lengths, radii, needed):
        """Return (Z, M, C) signed clearances (m) of capsules from every shape: exact (see
        above) where a quick bound is at most `needed`, that lower bound elsewhere.

        Args:
            segments: (M, C, 3, 2) capsule segment ends in the base frame (world.arm_capsules).
            half_lengths, radii: (C,) of the capsules (m).
            needed: a clearance (m) beyond which a lower bound will do, broadcastable to
                (Z, M, C) (e.g. how far each capsule may move).
        """
        m, c = segments.shape[:2]
        sums = segments.sum(axis=3).reshape(m * c, 3).T                 # 2 x middles, (3, MC)
        beyond = np.maximum(np.abs(self._half_rotation @ sums - self._offset) - self._half, 0.0)
        gap = np.sqrt((beyond * beyond).sum(axis=1)).reshape(-1, m, c) - \
            (self._grow[:, :, :1] + (half_lengths + radii))
        z, i, j = np.nonzero(gap <= needed)
        if len(z):
            ends = self._rotation[z] @ segments[i, j] - self._offset[z]            # (N, 3, 2)
            start = ends[:, :, 0].T
            span = ends[:, :, 1].T - start
            exact = np.empty(len(z))
            point = self._is_point[z]
            if point.any():
                exact[point] = segment_point(start[:, point], span[:, point])
            if not point.all():
                box = ~point
                exact[box] = segment_box(start[:, box], span[:, box], self._half[z[box], :, 0].T)
            exact -= self._grow[z, 0, 0]
            cylinder = self._is_cylinder[z]
            if cylinder.any():
                top = ends[:, 2]                                         # (N, 2) along the axis
                across = top[:, 0] * top[:, 1] <= 0.0
                slab = np.where(across, 0.0, np.abs(top).min(axis=1)) - self._slab[z]
                exact = np.where(cylinder, np.maximum(exact, slab), exact)
            gap[z, i, j] = np.maximum(gap[z, i, j], exact - radii[j])
        return gap
