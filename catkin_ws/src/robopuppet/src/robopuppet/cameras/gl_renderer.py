"""Offscreen OpenGL rendering of meshes into BGR images, through EGL on Mesa (no display).

Why OpenGL and not numpy or QPainter: Mesa's software rasteriser (llvmpipe) draws a 640x480
frame of the stand-in's world (about 5700 triangles) with a real depth buffer in 5 to 9 ms of
CPU, where a vectorised numpy ray cast costs about 45 ms per box over the whole image (64
shapes in the URDF and the world) and a painter's algorithm draws the arm behind the bed when
it reaches over it (docs/cameras.md). EGL's surfaceless platform needs neither an X display nor a
QGuiApplication, so the robot host runs it headless and Qt stays in gui/. Shading: one
directional light (Lambert) plus ambient, per vertex (the fixed-function pipeline of a
compatibility context).

A Renderer is bound to the thread that made it (an OpenGL context is current in one thread):
create it and call render() from the same thread. Not a ROS module: no rospy.
"""
import ctypes

import cv2
import numpy as np
from OpenGL import GL
# The raw pointer functions: PyOpenGL's wrapped ones keep the array alive in per-context data,
# which it finds through its platform (GLX), not through EGL's current context.
from OpenGL.raw.GL.VERSION.GL_1_1 import glColorPointer, glNormalPointer, glVertexPointer

NEAR_M, FAR_M = 0.01, 30.0  # clipping distances of every camera
LIGHT_DIRECTION = (0.35, -0.25, 1.0)  # towards the light, in the scene's frame (from above)
AMBIENT, DIFFUSE = 0.35, 0.7
_FLOATS_PER_VERTEX = 9  # position, normal, colour
# EGL 1.5 through ctypes, not PyOpenGL's OpenGL.EGL: that one works only when PyOpenGL was set
# to its EGL platform before anything imported OpenGL (pyqtgraph does, in the GUI and its tests).
# PyOpenGL's GL calls reach whichever context is current (libglvnd dispatches them).
_EGL_PLATFORM_SURFACELESS_MESA = 0x31DD
_EGL_SURFACE_TYPE, _EGL_PBUFFER_BIT = 0x3033, 0x0001
_EGL_RENDERABLE_TYPE, _EGL_OPENGL_BIT = 0x3040, 0x0008
_EGL_NONE, _EGL_OPENGL_API = 0x3038, 0x30A2


class RenderError(RuntimeError):
    """No OpenGL context could be made, or drawing failed."""


def _egl():
    """Return libEGL with the signatures used here."""
    try:
        egl = ctypes.CDLL('libEGL.so.1')
    except OSError as error:
        raise RenderError('no EGL library (Debian libegl1, libegl-mesa0): %s' % error) from None
    pointer, int32 = ctypes.c_void_p, ctypes.c_int32
    for name, result, arguments in (
            ('eglGetPlatformDisplay', pointer, [ctypes.c_uint, pointer, pointer]),
            ('eglInitialize', ctypes.c_uint, [pointer, ctypes.POINTER(int32),
                                              ctypes.POINTER(int32)]),
            ('eglChooseConfig', ctypes.c_uint, [pointer, ctypes.POINTER(int32),
                                                ctypes.POINTER(pointer), int32,
                                                ctypes.POINTER(int32)]),
            ('eglBindAPI', ctypes.c_uint, [ctypes.c_uint]),
            ('eglCreateContext', pointer, [pointer, pointer, pointer, pointer]),
            ('eglMakeCurrent', ctypes.c_uint, [pointer, pointer, pointer, pointer]),
            ('eglDestroyContext', ctypes.c_uint, [pointer, pointer])):
        function = getattr(egl, name)
        function.restype, function.argtypes = result, arguments
    return egl


def _egl_context():
    """Return (libEGL, display, context) of a current desktop OpenGL context, surfaceless."""
    egl = _egl()
    display = egl.eglGetPlatformDisplay(_EGL_PLATFORM_SURFACELESS_MESA, None, None)
    major, minor = ctypes.c_int32(), ctypes.c_int32()
    if not display or not egl.eglInitialize(display, ctypes.byref(major), ctypes.byref(minor)):
        raise RenderError('EGL has no surfaceless display (Mesa libegl-mesa0 missing?)')
    attributes = (ctypes.c_int32 * 5)(_EGL_SURFACE_TYPE, _EGL_PBUFFER_BIT,  # not a window
                                      _EGL_RENDERABLE_TYPE, _EGL_OPENGL_BIT, _EGL_NONE)
    config, count = ctypes.c_void_p(), ctypes.c_int32()
    if not egl.eglChooseConfig(display, attributes, ctypes.byref(config), 1,
                               ctypes.byref(count)) or count.value < 1:
        raise RenderError('EGL offers no configuration for desktop OpenGL')
    egl.eglBindAPI(_EGL_OPENGL_API)
    context = egl.eglCreateContext(display, config, None, None)
    if not context or not egl.eglMakeCurrent(display, None, None, context):
        raise RenderError('cannot make an OpenGL context current without a surface')
    return egl, display, context


def projection(k_matrix, width, height, near_m=NEAR_M, far_m=FAR_M):
    """Return the 4x4 OpenGL projection of a pinhole camera, for OpenGL eye coordinates.

    K = [fx 0 cx; 0 fy cy; 0 0 1] in ROS's convention (pixel (0, 0)'s centre at u = v = 0, v
    downwards); the image read back with its rows flipped (top row first) then puts the point
    (x, y, z) of the optical frame at u = fx x / z + cx, v = fy y / z + cy.
    """
    fx, cx, fy, cy = k_matrix[0][0], k_matrix[0][2], k_matrix[1][1], k_matrix[1][2]
    depth = far_m - near_m
    return np.array([
        [2.0 * fx / width, 0.0, 1.0 - 2.0 * (cx + 0.5) / width, 0.0],
        [0.0, 2.0 * fy / height, 2.0 * (cy + 0.5) / height - 1.0, 0.0],
        [0.0, 0.0, -(far_m + near_m) / depth, -2.0 * far_m * near_m / depth],
        [0.0, 0.0, -1.0, 0.0]])


def rigid_inverse(pose):
    """Return the inverse of a 4x4 rigid transform (rotation transposed).

    Not np.linalg.inv: LAPACK through OpenBLAS leaves its worker threads spinning in
    sched_yield after every call, which cost most of a core at 15 frames/s.
    """
    inverse = np.eye(4)
    inverse[:3, :3] = pose[:3, :3].T
    inverse[:3, 3] = -pose[:3, :3].T @ pose[:3, 3]
    return inverse


# The optical frame (x right, y down, z forward) seen from OpenGL's eye frame (y up, z back).
OPTICAL_TO_EYE = np.diag([1.0, -1.0, -1.0, 1.0])


class _Buffer:
    """One mesh in a vertex buffer object: interleaved position, normal, colour floats."""

    def __init__(self):
        self.count = 0
        self.name = GL.glGenBuffers(1)

    def load(self, mesh):
        """Replace the buffer's triangles by a mesh's."""
        data = np.ascontiguousarray(np.hstack([mesh.vertices, mesh.normals, mesh.colours]),
                                    np.float32)
        self.count = len(data)
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, self.name)
        GL.glBufferData(GL.GL_ARRAY_BUFFER, data.nbytes, data if len(data) else None,
                        GL.GL_DYNAMIC_DRAW)
        return self

    def draw(self):
        if not self.count:
            return
        stride = _FLOATS_PER_VERTEX * 4
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, self.name)
        glVertexPointer(3, GL.GL_FLOAT, stride, ctypes.c_void_p(0))  # offsets in the buffer
        glNormalPointer(GL.GL_FLOAT, stride, ctypes.c_void_p(12))
        glColorPointer(3, GL.GL_FLOAT, stride, ctypes.c_void_p(24))
        GL.glDrawArrays(GL.GL_TRIANGLES, 0, self.count)


class Renderer:
    """Draw a scene seen by pinhole cameras into width x height BGR images.

    The scene has three parts, each one mesh in the scene's frame: the still world (floor, bed,
    patient), the moving robot (posed by the caller and replaced whenever it moves) and
    translucent volumes (keep-out zones), drawn last without hiding what lies behind them.

    Args:
        width, height: pixels of every image.
        background: RGB colour (0..1) where nothing is drawn.
    Raises:
        RenderError: no OpenGL context (no EGL/Mesa on this host).
    """

    def __init__(self, width, height, background=(0.78, 0.82, 0.86)):
        self.width, self.height = int(width), int(height)
        self._egl, self._display, self._context = _egl_context()
        self._framebuffer = GL.glGenFramebuffers(1)
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, self._framebuffer)
        for attachment, kind in ((GL.GL_COLOR_ATTACHMENT0, GL.GL_RGBA8),
                                 (GL.GL_DEPTH_ATTACHMENT, GL.GL_DEPTH_COMPONENT24)):
            buffer = GL.glGenRenderbuffers(1)
            GL.glBindRenderbuffer(GL.GL_RENDERBUFFER, buffer)
            GL.glRenderbufferStorage(GL.GL_RENDERBUFFER, kind, self.width, self.height)
            GL.glFramebufferRenderbuffer(GL.GL_FRAMEBUFFER, attachment, GL.GL_RENDERBUFFER,
                                         buffer)
        if GL.glCheckFramebufferStatus(GL.GL_FRAMEBUFFER) != GL.GL_FRAMEBUFFER_COMPLETE:
            raise RenderError('OpenGL cannot render %dx%d offscreen' % (self.width, self.height))
        GL.glViewport(0, 0, self.width, self.height)
        GL.glClearColor(background[0], background[1], background[2], 1.0)
        GL.glEnable(GL.GL_DEPTH_TEST)
        GL.glEnable(GL.GL_CULL_FACE)
        GL.glEnable(GL.GL_LIGHTING)
        GL.glEnable(GL.GL_LIGHT0)
        GL.glEnable(GL.GL_COLOR_MATERIAL)
        GL.glColorMaterial(GL.GL_FRONT_AND_BACK, GL.GL_AMBIENT_AND_DIFFUSE)
        GL.glLightModelfv(GL.GL_LIGHT_MODEL_AMBIENT, (AMBIENT, AMBIENT, AMBIENT, 1.0))
        GL.glLightfv(GL.GL_LIGHT0, GL.GL_DIFFUSE, (DIFFUSE, DIFFUSE, DIFFUSE, 1.0))
        GL.glLightfv(GL.GL_LIGHT0, GL.GL_AMBIENT, (0.0, 0.0, 0.0, 1.0))
        GL.glBlendFunc(GL.GL_SRC_ALPHA, GL.GL_ONE_MINUS_SRC_ALPHA)
        GL.glPixelStorei(GL.GL_PACK_ALIGNMENT, 1)
        for array in (GL.GL_VERTEX_ARRAY, GL.GL_NORMAL_ARRAY, GL.GL_COLOR_ARRAY):
            GL.glEnableClientState(array)
        self._world, self._robot, self._zones = _Buffer(), _Buffer(), _Buffer()
        self._zone_rgba = (1.0, 0.0, 0.0, 0.35)
        self._pixels = np.empty((self.height, self.width, 4), np.uint8)

    def _make_current(self):
        """Make this renderer's context the thread's current one (another Renderer may have
        taken its place)."""
        if self._context is None:
            raise RenderError('the renderer is closed')
        if not self._egl.eglMakeCurrent(self._display, None, None, self._context):
            raise RenderError('cannot make the OpenGL context current in this thread')

    def set_world(self, mesh):
        """Set the still part of the scene (a mesh in the scene's frame)."""
        self._make_current()
        self._world.load(mesh)

    def set_robot(self, mesh):
        """Set the moving part of the scene, posed (a mesh in the scene's frame)."""
        self._make_current()
        self._robot.load(mesh)

    def set_zones(self, mesh, rgba=(1.0, 0.0, 0.0, 0.35)):
        """Set the translucent volumes (a mesh in the scene's frame), drawn in one colour."""
        self._make_current()
        self._zones.load(mesh)
        self._zone_rgba = tuple(float(c) for c in rgba)

    def render(self, camera_pose, k_matrix):
        """Return the BGR image (height, width, 3 uint8, a new array) seen by a camera.

        Args:
            camera_pose: 4x4 pose of the camera's optical frame (x right, y down, z forward)
                in the scene's frame.
            k_matrix: 3x3 intrinsics (nested lists or array), see projection().
        """
        self._make_current()
        GL.glClear(GL.GL_COLOR_BUFFER_BIT | GL.GL_DEPTH_BUFFER_BIT)
        GL.glMatrixMode(GL.GL_PROJECTION)
        GL.glLoadMatrixd(projection(k_matrix, self.width, self.height).T.ravel())
        GL.glMatrixMode(GL.GL_MODELVIEW)
        view = OPTICAL_TO_EYE @ rigid_inverse(np.asarray(camera_pose, np.float64))
        GL.glLoadMatrixd(view.T.ravel())
        GL.glLightfv(GL.GL_LIGHT0, GL.GL_POSITION, tuple(LIGHT_DIRECTION) + (0.0,))
        self._world.draw()
        self._robot.draw()
        if self._zones.count:
            GL.glEnable(GL.GL_BLEND)
            GL.glDisable(GL.GL_CULL_FACE)  # tinted from inside a zone too
            GL.glDepthMask(GL.GL_FALSE)  # a zone does not hide what lies in or behind it
            GL.glDisableClientState(GL.GL_COLOR_ARRAY)
            GL.glColor4f(*self._zone_rgba)
            self._zones.draw()
            GL.glEnableClientState(GL.GL_COLOR_ARRAY)
            GL.glDepthMask(GL.GL_TRUE)
            GL.glEnable(GL.GL_CULL_FACE)
            GL.glDisable(GL.GL_BLEND)
        # RGBA is llvmpipe's fast read path; OpenGL's rows run bottom-up.
        GL.glReadPixels(0, 0, self.width, self.height, GL.GL_RGBA, GL.GL_UNSIGNED_BYTE,
                        self._pixels)
        return cv2.cvtColor(cv2.flip(self._pixels, 0), cv2.COLOR_RGBA2BGR)

    def close(self):
        """Release the OpenGL context (the Renderer cannot render afterwards)."""
        if self._context is not None:
            self._egl.eglMakeCurrent(self._display, None, None, None)
            self._egl.eglDestroyContext(self._display, self._context)
            self._context = None
