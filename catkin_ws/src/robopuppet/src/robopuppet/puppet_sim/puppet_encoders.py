"""The simulated puppet's seven encoders: raw angles and statuses from the mechanical angles.

Pure: no clock, no I/O, no rospy. Joints 1, 3, 5 are absolute (hall) encoders whose raw angle
is the mechanical angle; one missing at power-on reports Disconnected (and the firmware angle
0). Joints 0, 2, 4, 6 are quadrature encoders whose raw angle is counted from power-on and
report Uncalibrated until they first pass their index mark at mechanical angle 0 (any multiple
of 2 pi), which zeroes the count; then Working, with raw = the mechanical angle. The firmware
(puppet_model) applies home and sign to the raw angle.
"""
import math

from robopuppet import settings
from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_arm import wrap

HALL_RAD_PER_COUNT = 2.0 * math.pi / 2 ** 14   # AS5048B, 14 bits
QUAD_RAD_PER_COUNT = 2.0 * math.pi / 2 ** 13   # 8192 counts per revolution
INDEX_HALF_WIDTH_RAD = 0.005  # the index pulse is about 0.6 degrees wide


class Encoders:
    """The encoders of an arm that powered on at pose_rad (mechanical angles, rad).

    Args:
        pose_rad: the seven mechanical angles at power-on.
        hall_disconnected: hall-encoder joints (of 1, 3, 5) missing at power-on, for good.

    Raises:
        ValueError: a joint in hall_disconnected is not a hall-encoder joint.
    """

    def __init__(self, pose_rad, hall_disconnected=()):
        missing = set(hall_disconnected)
        if not missing <= set(settings.HALL_JOINTS):
            raise ValueError('only hall-encoder joints %s can be disconnected, got %s'
                             % (list(settings.HALL_JOINTS), sorted(missing)))
        hall = settings.HALL_JOINTS
        self.hall_working = [j in hall and j not in missing for j in settings.JOINTS]
        self.calibrated = [j in hall for j in settings.JOINTS]  # quadrature: after the index
        self._count_origin_rad = list(pose_rad)  # quadrature counts are relative to this

    def status(self, joint):
        """Return the codec encoder status of a joint (WORKING, DISCONNECTED, UNCALIBRATED)."""
        if joint in settings.HALL_JOINTS:
            return codec.WORKING if self.hall_working[joint] else codec.DISCONNECTED
        return codec.WORKING if self.calibrated[joint] else codec.UNCALIBRATED

    def raw_rad(self, joint, mechanical_rad):
        """Return a joint's raw angle (rad, in whole counts), or None while it is disconnected."""
        if joint in settings.HALL_JOINTS:
            if not self.hall_working[joint]:
                return None
            return _counts(mechanical_rad % (2.0 * math.pi), HALL_RAD_PER_COUNT)
        # counted from power-on, or from the index mark once it has been passed
        return _counts(mechanical_rad - self._count_origin_rad[joint], QUAD_RAD_PER_COUNT)

    def move(self, before_rad, after_rad):
        """Track the arm's move from before_rad to after_rad (mechanical, rad): a quadrature
        joint that meets its index mark is calibrated and its count zeroed."""
        for joint in settings.QUAD_JOINTS:
            if _passes_index(before_rad[joint], after_rad[joint]):
                self.calibrated[joint] = True
                self._count_origin_rad[joint] = 0.0  # the index pulse zeroes the count


def _counts(angle_rad, rad_per_count):
    """Return angle_rad as the encoder counts it (whole counts)."""
    return round(angle_rad / rad_per_count) * rad_per_count


def _passes_index(before_rad, after_rad):
    """Return True if a joint moving from before_rad to after_rad meets its index mark."""
    period = 2.0 * math.pi
    if math.floor(before_rad / period) != math.floor(after_rad / period):
        return True
    return abs(wrap(after_rad)) <= INDEX_HALF_WIDTH_RAD
