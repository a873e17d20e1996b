"""arm_X's keep-out zones: the zone file it reads and the zones it shows RViz (an adapter).

The zones bind the arm controller (world.zones.ZoneGuard, wired in through teleop.Teleop); this
module reads them and draws them, the zones holding Baxter's arms back highlighted (ZoneView).
docs/zones.md describes both. The replay (episodes.replay_node) reads the same files the running
arm controllers were given, through here.
"""
import os

import rospkg
import rospy
from visualization_msgs.msg import Marker, MarkerArray

from robopuppet import baxter_description as bd, interface, shape_markers
from robopuppet.world import arm_capsules, zones

ZONE_COLOUR = (0.9, 0.1, 0.1)   # a zone without a colour of its own
ZONE_ALPHA = 0.3                # translucent: what is inside stays visible
NAME_COLOUR = (1.0, 1.0, 1.0, 0.9)
NAMESPACE, NAME_NAMESPACE = 'keep-out zones', 'keep-out zone names'
HELD_NAMESPACE = 'keep-out zones holding Baxter'   # and the node's name: one per controller
HELD_COLOUR = (1.0, 0.45, 0.0, 0.85)      # strong orange over the red: the zone holding an arm
HELD_TEXT_COLOUR = (1.0, 0.6, 0.1, 1.0)
HELD_GROW_M = 0.005                       # drawn just outside the zone's own marker
MIN_REPUBLISH_S = 0.2                     # a zone flickering at the command rate costs little
TEXT_HEIGHT_M = shape_markers.TEXT_HEIGHT_M
ZONES_PARAM = 'zones_file'   # arm_X's ~zones_file: arm.launch sets /arm_L/zones_file, ...


def zones_file():
    """Return ~zones_file: '' (the default) for no zones; arm.launch's zones_file sets it."""
    return rospy.get_param('~' + ZONES_PARAM, '')


def controllers_zones_files():
    """Return {puppet side: zone file} that the arm controllers arm_L and arm_R were given, as
    the parameter server holds it ('' for none); a side whose parameter is not set is left out.
    """
    names = {side: interface.node_param('arm', side, ZONES_PARAM)
             for side in interface.PUPPET_SIDES}
    return {side: str(rospy.get_param(name)) for side, name in names.items()
            if rospy.has_param(name)}


def package_zones_file():
    """Return the package's zone file, config/zones.yaml (arm.launch's default too)."""
    return os.path.join(rospkg.RosPack().get_path('robopuppet'), 'config', 'zones.yaml')


def load_guards(*paths):
    """Return ({side: ZoneGuard}, zone Shapes) for zone files, each zone once ('' : none; no
    file named, or only '': no guards).

    Raises:
        ValueError (world.zones.ZoneFileError, arm_capsules.CapsuleError, DescriptionError): a bad
            zone file or robot description, named; arm_X does not start without its zones.
    """
    paths = [path for path in paths if path]
    if not paths:
        return {}, []
    found = []
    for path in paths:
        found += [zone for zone in zones.load_zones(path) if zone not in found]
    text = bd.read_urdf(bd.urdf_path(rospkg.RosPack().get_path('robopuppet')))
    description = bd.Description(text)
    return ({side: zones.ZoneGuard(arm_capsules.ArmCapsules(description, text, side), found)
             for side in interface.BAXTER_SIDES}, found)


def _held_text(zone, sides):
    return "'%s' holds back Baxter's %s arm%s" % (zone, ' and '.join(sides),
                                                   's' if len(sides) > 1 else '')


def zone_markers(found, stamp):
    """Return the MarkerArray of zones: a DELETEALL (zones of an earlier file go), then each
    zone translucent red in Baxter's base frame and its name above it."""
    markers = [Marker(ns=NAMESPACE, action=Marker.DELETEALL)]
    for index, shape in enumerate(found):
        markers += [shape_markers.shape_marker(shape, NAMESPACE, index,
                                               (shape.colour or ZONE_COLOUR) + (ZONE_ALPHA,)),
                    shape_markers.text_marker(NAME_NAMESPACE, index, shape.name,
                                              shape_markers.label_xyz(shape), NAME_COLOUR)]
    return shape_markers.marker_array(markers, stamp)


def held_markers(found, stamp, holding, name):
    """Return all of controller `name`'s highlights: each zone in `holding` ({zone name: [Baxter
    sides]}) drawn over in HELD_COLOUR, a line above saying which arm it holds; the others'
    deleted. Its own namespace and no DELETEALL: the other controller's highlights stay."""
    ns, markers = '%s (%s)' % (HELD_NAMESPACE, name), []
    for index, shape in enumerate(found):
        text_id = len(found) + index
        if shape.name not in holding:
            markers += [Marker(ns=ns, id=index, action=Marker.DELETE),
                        Marker(ns=ns, id=text_id, action=Marker.DELETE)]
            continue
        x, y, z = shape_markers.label_xyz(shape)
        markers += [
            shape_markers.shape_marker(shape, ns, index, HELD_COLOUR, HELD_GROW_M),
            shape_markers.text_marker(ns, text_id, _held_text(shape.name, holding[shape.name]),
                                      (x, y, z + 1.6 * TEXT_HEIGHT_M), HELD_TEXT_COLOUR)]
    return shape_markers.marker_array(markers, stamp)


def holding_zones(zone_left, zone_right):
    """Return {zone name: [Baxter sides]} of teleop_state's zone_left, zone_right ('' none)."""
    holding = {}
    for zone, side in zip((zone_left, zone_right), interface.BAXTER_SIDES):
        if zone:
            holding.setdefault(zone, []).append(side)
    return holding


class ZoneView:
    """Republish this controller's highlights when the zones holding Baxter's arms change, at most
    every MIN_REPUBLISH_S (a later report publishes a change held back); never raises: a failed
    publish is logged, and the commands go on."""

    def __init__(self, publisher, found, name):
        self._publisher, self._found, self._name = publisher, found, name
        self._shown, self._shown_s = {}, float('-inf')

    def show(self, now_s, zone_left, zone_right):
        """Take teleop_state's zones at now_s (monotonic s); republish if they changed."""
        try:
            holding = holding_zones(zone_left, zone_right)
            if not self._found or holding == self._shown or \
                    now_s - self._shown_s < MIN_REPUBLISH_S:
                return
            self._publisher.publish(held_markers(self._found, rospy.Time.now(), holding,
                                                 self._name))
            self._shown, self._shown_s = holding, now_s
        except Exception as error:  # markers are for the eye; commands must not notice
            rospy.logerr_throttle(10, '%s: zone markers not published: %s', self._name, error)


def publish_zones(found, name):
    """Publish the zones, latched, on interface.ZONE_MARKERS, and no highlight on
    interface.ZONE_HOLD_MARKERS; return the ZoneView that highlights the zones holding arms back
    (name: the node's, for its namespace and log lines)."""
    zones_pub = rospy.Publisher(interface.ZONE_MARKERS, MarkerArray, queue_size=1, latch=True)
    zones_pub.publish(zone_markers(found, rospy.Time.now()))
    held_pub = rospy.Publisher(interface.ZONE_HOLD_MARKERS, MarkerArray, queue_size=1, latch=True)
    held_pub.publish(held_markers(found, rospy.Time.now(), {}, name))
    return ZoneView(held_pub, found, name)
