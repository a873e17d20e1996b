"""What config_X's stored settings tell arm_X about the meaning of the puppet's angles (pure).

A change of a setting of settings.ANGLE_SETTINGS (home_angle, sign_angle, the angle and speed
limits) changes the angle the puppet reports while the hand stays still, so it must stop
following: the watch names the settings that changed between two stored_settings messages (the
first one after start-up is no change). The change and the samples with the new meaning travel
on different connections (stored_settings from config_X, joint_states from serial_X), so the
samples carry their meaning: serial_X tags each one (header.frame_id) with settings.angle_tag of
the settings it has begun to send to the device, and a sample whose tag is not that of the
newest stored settings known here is refused, whichever of the two arrives first.
docs/teleop.md, "Settings that change the angle", gives the reasoning.
"""
from robopuppet import settings


class AngleSettingsWatch:
    """Follow the angle settings of config_X's stored settings; judge puppet samples' tags.

    Attributes:
        tag: settings.angle_tag of the newest stored settings, None before any.
        refused: puppet samples refused so far for their tag.
    """

    def __init__(self):
        self.tag = None
        self.refused = 0
        self._values = None   # {(joint, name): value} of the newest stored settings

    def on_stored(self, joints):
        """Take config_X's stored settings; return the [(joint, name)] of ANGLE_SETTINGS whose
        value differs from the last stored settings taken ([] for the first ones).

        Args:
            joints: [(joint, {name: value})], one per joint 0..6 (every name of ANGLE_SETTINGS).
        Raises:
            ValueError: not one each of joints 0..6, or a setting missing (nothing taken).
        """
        by_joint = dict(joints)
        if sorted(joint for joint, _ in joints) != list(settings.JOINTS):
            raise ValueError('joints %s, not one each of 0..6'
                             % sorted(joint for joint, _ in joints)[:10])
        try:
            values = {(j, n): float(by_joint[j][n]) for j in settings.JOINTS
                      for n in settings.ANGLE_SETTINGS}
        except (KeyError, TypeError, ValueError) as error:
            raise ValueError('a setting is missing or no number: %s' % error) from None
        old, self._values = self._values, values
        self.tag = settings.angle_tag([{n: values[j, n] for n in settings.ANGLE_SETTINGS}
                                       for j in settings.JOINTS])
        if old is None:
            return []
        return [key for key in sorted(values) if not _same(values[key], old[key])]

    def refusal(self, tag):
        """Return '' when a puppet sample tagged `tag` (its header.frame_id) may be followed,
        else why not (and count it). An untagged sample ('': a test or a tool, not serial_X)
        passes; a tagged one only with the tag of the newest stored settings."""
        if not tag or tag == self.tag:
            return ''
        self.refused += 1
        if self.tag is None:
            return ("made with angle settings (%s) before config_X's stored settings came"
                    % tag[:40])
        return ('made with other angle settings (home, sign or limits) than the ones '
                'config_X stored last: not followed until the two agree')


def describe(changes):
    """Return e.g. "joint 0's home_angle and sign_angle, joint 2's angle_max" for
    [(joint, name)]."""
    joints = {}
    for joint, name in changes:
        joints.setdefault(joint, []).append(name)
    return ', '.join("joint %d's %s" % (joint, ' and '.join(names))
                     for joint, names in sorted(joints.items()))


def _same(a, b):
    return a == b or (a != a and b != b)   # NaN is no change of NaN
