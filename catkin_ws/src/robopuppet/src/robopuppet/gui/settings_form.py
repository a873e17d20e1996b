"""Checks for what the operator types into a joint tab, before anything is sent.

Pure: no Qt, no ROS. The rules are config_store.check_request's (the config node's), applied to
the whole form, so the GUI refuses exactly what the config node would refuse.
"""
import math

from robopuppet import settings
from robopuppet.config import config_store


class EntryError(ValueError):
    """One or more entries are refused; str() is a message for the operator, one line each."""


def field_text(value):
    """Return the text that shows a float32 setting exactly and plainly: '10', '1.571', '1e-05'.

    (config_store.format_value is the shortest exact text, which may read '1e+01'.)
    """
    text = repr(float(config_store.format_value(value)))
    return text[:-2] if text.endswith('.0') else text


def parse_form(joint, texts):
    """Turn the twelve setting fields of a joint tab into numbers.

    Args:
        joint: joint index 0..6.
        texts: {setting name: text typed by the operator} for every name in settings.NAMES.
    Returns:
        {name: float32 value} for every setting.
    Raises:
        EntryError: a field that is not a number, not finite, a sign that is not +-1, outside
            its bound, or a minimum above its maximum (all problems, one per line).
    """
    values, errors = {}, []
    for name in settings.NAMES:
        text = texts[name].strip()
        try:
            values[name] = config_store.to_float32(float(text))
        except ValueError:
            errors.append('%s: %r is not a number' % (name, text))
    if errors:
        raise EntryError('\n'.join(errors))
    try:
        return config_store.check_request(values, joint, settings.NAMES,
                                          [values[name] for name in settings.NAMES])
    except config_store.InvalidSetting as error:
        raise EntryError('\n'.join(error.problems)) from None


def parse_setpoint(text, stored=None):
    """Turn a setpoint entry into an angle in rad.

    Args:
        text: what the operator typed.
        stored: the joint's {name: value} if known; the setpoint must then lie within
            [angle_min, angle_max] (the firmware would clamp it silently).
    Raises:
        EntryError: not a finite number, or outside the angle limits.
    """
    try:
        angle_rad = float(text.strip())
    except ValueError:
        raise EntryError('setpoint: %r is not a number' % text.strip()) from None
    if not math.isfinite(angle_rad):
        raise EntryError('setpoint: %r is not a finite number' % text.strip())
    if stored is not None and not stored['angle_min'] <= angle_rad <= stored['angle_max']:
        raise EntryError('setpoint: %s rad is outside the angle limits [%s, %s]' % (
            field_text(angle_rad), field_text(stored['angle_min']),
            field_text(stored['angle_max'])))
    return angle_rad
