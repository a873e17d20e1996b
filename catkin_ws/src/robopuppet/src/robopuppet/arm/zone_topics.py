"""arm_X's keep-out zones: the zone file it reads and the zones it shows RViz (an adapter).

The zones bind the arm controller (world.zones.ZoneGuard, wired in through teleop.Teleop); this
module reads them and draws them. docs/zones.md describes both. The replay (episodes.replay_node)
reads the same files the running arm controllers were given, through here.
"""
import os

import rospkg
import rospy
from geometry_msgs.msg import Point, Pose, Quaternion, Vector3
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from robopuppet import baxter_description as bd, interface
from robopuppet.world import arm_capsules, zones

ZONE_COLOUR = (0.9, 0.1, 0.1)   # a zone without a colour of its own
ZONE_ALPHA = 0.3                # translucent: what is inside stays visible
NAMESPACE, NAME_NAMESPACE = 'keep-out zones', 'keep-out zone names'
TEXT_HEIGHT_M = 0.05
ZONES_PARAM = 'zones_file'   # arm_X's ~zones_file: arm.launch sets /arm_L/zones_file, ...


def zones_file():
    """Return ~zones_file: '' (the default) for no zones; arm.launch's zones_file sets it."""
    return rospy.get_param('~' + ZONES_PARAM, '')


def controllers_zones_files():
    """Return {puppet side: zone file} that the arm controllers arm_L and arm_R were given, as
    the parameter server holds it ('' for none); a side whose parameter is not set is left out.
    """
    names = {side: '/arm_%s/%s' % (side, ZONES_PARAM) for side in interface.PUPPET_SIDES}
    return {side: str(rospy.get_param(name)) for side, name in names.items()
            if rospy.has_param(name)}


def package_zones_file():
    """Return the package's zone file, config/zones.yaml (arm.launch's default too)."""
    return os.path.join(rospkg.RosPack().get_path('robopuppet'), 'config', 'zones.yaml')


def load_guards(*paths):
    """Return ({side: ZoneGuard}, zone Shapes) for zone files, each zone once ('' : none; no
    file named, or only '': no guards).

    Raises:
        ValueError (world.zones.ZoneFileError, arm_capsules.CapsuleError): a bad zone file or
            robot description, named in the message; arm_X does not start without its zones.
    """
    paths = [path for path in paths if path]
    if not paths:
        return {}, []
    found = []
    for path in paths:
        found += [zone for zone in zones.load_zones(path) if zone not in found]
    urdf = bd.urdf_path(rospkg.RosPack().get_path('robopuppet'))
    with open(urdf) as stream:
        text = stream.read()
    description = bd.Description(text)
    return ({side: zones.ZoneGuard(arm_capsules.ArmCapsules(description, text, side), found)
             for side in interface.BAXTER_SIDES}, found)


def _marker(shape, index):
    quaternion = bd.matrix_quaternion(bd.rpy_matrix(*shape.rpy))
    marker = Marker(ns=NAMESPACE, id=index, action=Marker.ADD,
                    pose=Pose(Point(*shape.xyz), Quaternion(*quaternion)),
                    color=ColorRGBA(*(shape.colour or ZONE_COLOUR) + (ZONE_ALPHA,)))
    if shape.type == 'box':
        marker.type, marker.scale = Marker.CUBE, Vector3(*shape.size)
    elif shape.type == 'sphere':
        marker.type, marker.scale = Marker.SPHERE, Vector3(*[2.0 * shape.radius] * 3)
    else:
        marker.type = Marker.CYLINDER
        marker.scale = Vector3(2.0 * shape.radius, 2.0 * shape.radius, shape.length)
    return marker


def _label(shape, index):
    top = shape.xyz[2] + (shape.size[2] / 2.0 if shape.type == 'box' else shape.radius)
    return Marker(ns=NAME_NAMESPACE, id=index, action=Marker.ADD, type=Marker.TEXT_VIEW_FACING,
                  text=shape.name, scale=Vector3(0.0, 0.0, TEXT_HEIGHT_M),
                  pose=Pose(Point(shape.xyz[0], shape.xyz[1], top + TEXT_HEIGHT_M),
                            Quaternion(0.0, 0.0, 0.0, 1.0)),
                  color=ColorRGBA(1.0, 1.0, 1.0, 0.9))


def zone_markers(found, stamp):
    """Return the MarkerArray of zones: a DELETEALL (zones of an earlier file go), then each
    zone translucent red in Baxter's base frame, and its name above it."""
    markers = [Marker(ns=NAMESPACE, action=Marker.DELETEALL)]
    for index, shape in enumerate(found):
        markers += [_marker(shape, index), _label(shape, index)]
    for marker in markers:
        marker.header.frame_id, marker.header.stamp = bd.BASE_FRAME, stamp
    return MarkerArray(markers=markers)


def publish_zones(found):
    """Publish the zones once, latched, on interface.ZONE_MARKERS; return the publisher."""
    publisher = rospy.Publisher(interface.ZONE_MARKERS, MarkerArray, queue_size=1, latch=True)
    publisher.publish(zone_markers(found, rospy.Time.now()))
    return publisher
