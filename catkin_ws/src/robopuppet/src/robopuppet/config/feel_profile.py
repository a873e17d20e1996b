"""Feel mode's gentle gains: the [feel] section's values and the settings they make active.

Pure: no file, clock or ROS. In feel mode the puppet holds (the device's hold) a pose streamed
from Baxter's measured pose, with gentle gains so that the operator feels only where Baxter
cannot follow (docs/feel.md). config_X lays these over the stored joint settings while
<ns>/opmode is feel and publishes the result as active_settings; they are never stored in a
joint's settings, so a crash in feel mode leaves the file right.
"""
import math

from robopuppet import interface, settings
from robopuppet.float32 import format_value, to_float32

PROFILE = interface.FEEL_PROFILE  # ArmSettings.profile of the feel settings ('': as stored)

# The comment written above a [feel] section that a file did not have yet.
INTRO = ["# Feel mode's gentle gains, laid over the joints' settings only while the opmode is",
         '# feel (never stored in a joint section): pid_kp and pid_kd x gain_scale, pid_ki 0,',
         '# voltage_min/voltage_max clipped to +-voltage_limit.']
INTRO += ['#   %-13s %-10s %s' % (s.name, s.unit or '-', s.meaning) for s in settings.FEEL_SETTINGS]


def feel_values(raw):
    """Return ({name: float32 value} of every feel setting, problems) from {name: text}.

    A missing section or option is the default without a problem (a file from before feel mode);
    a value that is not a number or outside its bound is the default, with a problem naming
    section, option, value and bound.
    """
    feel, problems = {}, []
    for setting in settings.FEEL_SETTINGS:
        feel[setting.name] = to_float32(setting.default)
        text_value = raw.get(setting.name)
        if text_value is None:
            continue
        try:
            number = to_float32(float(text_value))
        except ValueError:
            reason = 'not a number'
        else:
            reason = '' if math.isfinite(number) and setting.low < number <= setting.high else (
                'outside its bound (%s, %s]%s' % (format_value(setting.low),
                                                  format_value(setting.high),
                                                  ' ' + setting.unit if setting.unit else ''))
        if reason:
            problems.append('[%s] %s = %s: invalid (%s), using default %s' % (
                settings.FEEL_SECTION, setting.name, text_value, reason,
                format_value(setting.default)))
        else:
            feel[setting.name] = number
    return feel, problems


def feel_joint(values, feel):
    """Return one joint's {name: value} with feel mode's gentle gains laid over it.

    pid_kp and pid_kd are scaled by gain_scale, pid_ki is 0 (no integral wind-up against a
    Baxter that cannot follow), and the PID voltage range is clipped to
    [-voltage_limit, +voltage_limit] (a stored range outside it collapses to its nearer end, so
    that minimum <= maximum holds). Every other setting is as stored; values are float32.

    Args:
        values: the joint's stored {name: value} (every name of settings.NAMES).
        feel: {name: value} of settings.FEEL_SETTINGS (feel_values').
    """
    scale, limit = feel['gain_scale'], feel['voltage_limit']
    active = dict(values)
    active['pid_kp'] = to_float32(values['pid_kp'] * scale)
    active['pid_ki'] = 0.0
    active['pid_kd'] = to_float32(values['pid_kd'] * scale)
    active['voltage_min'] = to_float32(min(max(values['voltage_min'], -limit), limit))
    active['voltage_max'] = to_float32(max(min(values['voltage_max'], limit), -limit))
    return active


def active_joints(profile, joints, feel):
    """Return the joints' settings the device should hold in a profile ('' or PROFILE).

    Args:
        profile: '' for the stored settings as they are, PROFILE for feel_joint's.
        joints: [{name: value} of joint 0, ..., joint 6], as stored.
        feel: the [feel] values.
    Raises:
        ValueError: an unknown profile.
    """
    if profile == '':
        return [dict(values) for values in joints]
    if profile == PROFILE:
        return [feel_joint(values, feel) for values in joints]
    raise ValueError('unknown settings profile %r: use \'\' or %r' % (profile, PROFILE))
