"""Triangle meshes of the simple shapes the simulated cameras draw: boxes, cylinders, spheres.

Pure numpy. Shapes follow URDF geometry: a box is centred with its full size per axis, a
cylinder is centred on its z axis, a sphere on its origin. Every triangle winds counter-
clockwise seen from outside, so OpenGL's back-face culling hides the inside of closed shapes (a
hand camera sits inside Baxter's hand cylinder). A Mesh holds float32 (n, 3) arrays: vertices
(m), unit normals, and RGB colours in 0..1, three rows per triangle.
"""
import collections
import math

import numpy as np

Mesh = collections.namedtuple('Mesh', 'vertices normals colours')

CYLINDER_SEGMENTS = 24
SPHERE_RINGS = 12


def _mesh(vertices, normals, colour):
    vertices = np.asarray(vertices, np.float32).reshape(-1, 3)
    normals = np.asarray(normals, np.float32).reshape(-1, 3)
    colours = np.tile(np.asarray(colour, np.float32)[:3], (len(vertices), 1))
    return Mesh(vertices, normals, colours)


def box(size, colour):
    """Return the mesh of a box of size (x, y, z) m centred on the origin."""
    half = np.asarray(size, np.float64) / 2.0
    vertices, normals = [], []
    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for sign in (1.0, -1.0):
            normal = np.zeros(3)
            normal[axis] = sign
            corners = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                corner = np.zeros(3)
                corner[axis], corner[u], corner[v] = sign * half[axis], a * half[u], b * half[v]
                corners.append(corner)
            if sign < 0:  # keep the winding counter-clockwise seen from outside
                corners = corners[::-1]
            for i in (0, 1, 2, 0, 2, 3):
                vertices.append(corners[i])
                normals.append(normal)
    return _mesh(vertices, normals, colour)


def cylinder(radius, length, colour, segments=CYLINDER_SEGMENTS):
    """Return the mesh of a closed cylinder (radius, length m) along z, centred on the origin."""
    angles = np.linspace(0.0, 2.0 * math.pi, segments + 1)
    ring = np.stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)], axis=1)
    top, bottom = np.array([0.0, 0.0, length / 2.0]), np.array([0.0, 0.0, -length / 2.0])
    vertices, normals = [], []
    for i in range(segments):
        a, b = ring[i], ring[i + 1]
        quad = (radius * a + bottom, radius * b + bottom, radius * b + top, radius * a + top)
        for j, n in ((0, a), (1, b), (2, b), (0, a), (2, b), (3, a)):
            vertices.append(quad[j])
            normals.append(n)
        vertices += [top, radius * a + top, radius * b + top]
        normals += [(0.0, 0.0, 1.0)] * 3
        vertices += [bottom, radius * b + bottom, radius * a + bottom]
        normals += [(0.0, 0.0, -1.0)] * 3
    return _mesh(vertices, normals, colour)


def sphere(radius, colour, rings=SPHERE_RINGS):
    """Return the mesh of a sphere of radius m centred on the origin."""
    theta = np.linspace(0.0, math.pi, rings + 1)  # from the north pole down
    phi = np.linspace(0.0, 2.0 * math.pi, 2 * rings + 1)

    def point(i, j):
        return np.array([math.sin(theta[i]) * math.cos(phi[j]),
                         math.sin(theta[i]) * math.sin(phi[j]), math.cos(theta[i])])

    vertices, normals = [], []
    for i in range(rings):
        for j in range(2 * rings):
            p00, p10, p11, p01 = point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1)
            for tri in ((p00, p10, p11), (p00, p11, p01)):
                if np.linalg.norm(np.cross(tri[1] - tri[0], tri[2] - tri[0])) < 1e-12:
                    continue  # the degenerate half of a quad at a pole
                for p in tri:
                    vertices.append(radius * p)
                    normals.append(p)
    return _mesh(vertices, normals, colour)


def transformed(mesh, pose):
    """Return a mesh moved by a 4x4 rigid transform."""
    rotation, shift = pose[:3, :3], pose[:3, 3]
    return Mesh((mesh.vertices @ rotation.T + shift).astype(np.float32),
                (mesh.normals @ rotation.T).astype(np.float32), mesh.colours)


def merged(meshes):
    """Return one mesh holding all the given meshes' triangles (an empty mesh for none)."""
    meshes = list(meshes)
    if not meshes:
        empty = np.zeros((0, 3), np.float32)
        return Mesh(empty, empty, empty)
    return Mesh(*(np.concatenate([getattr(m, f) for m in meshes]) for f in Mesh._fields))


def checkerboard(size_m, tile_m, z_m, colours):
    """Return a square floor of size_m at height z_m (facing up) in tiles of two colours."""
    count = max(1, int(round(size_m / tile_m)))
    tile = size_m / count
    start = -size_m / 2.0
    vertices, cols = [], []
    for i in range(count):
        for j in range(count):
            x0, y0 = start + i * tile, start + j * tile
            corners = [(x0, y0, z_m), (x0 + tile, y0, z_m), (x0 + tile, y0 + tile, z_m),
                       (x0, y0 + tile, z_m)]
            for k in (0, 1, 2, 0, 2, 3):
                vertices.append(corners[k])
                cols.append(colours[(i + j) % 2])
    vertices = np.asarray(vertices, np.float32)
    normals = np.tile(np.array([0.0, 0.0, 1.0], np.float32), (len(vertices), 1))
    return Mesh(vertices, normals, np.asarray(cols, np.float32))
