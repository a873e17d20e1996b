"""Checks for what the operator types into a joint tab, before anything is sent.

Pure: no Qt, no ROS. The rules are config_store.check_request's (the config node's), applied to
the whole form, so the GUI refuses exactly what the config node would refuse.
"""
import math
import re

from robopuppet import settings
from robopuppet.config import config_store


class EntryError(ValueError):
    """One or more entries are refused; str() is a message for the operator, one line each.

    .problems is [(names of the fields concerned, text)], one per problem, every problem at
    once (a field may have several; a minimum above its maximum concerns both fields).
    """

    def __init__(self, problems):
        super().__init__('\n'.join(text for _, text in problems))
        self.problems = list(problems)

    def by_field(self):
        """Return {setting name: [problem texts]} for every field with a problem."""
        fields = {}
        for names, text in self.problems:
            for name in names:
                fields.setdefault(name, []).append(text)
        return fields


def named_fields(problem):
    """Return the setting names a problem text mentions, in settings.NAMES order."""
    return tuple(name for name in settings.NAMES
                 if re.search(r'(?<![A-Za-z_])%s(?![A-Za-z_])' % name, problem))


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
            its bound, or a minimum above its maximum: every problem at once, each with the
            fields it concerns (a pair whose other half is refused is not compared).
    """
    typed = [texts[name].strip() for name in settings.NAMES]
    # A text that is not a number goes to the checks as it is: they refuse it ('not a
    # number') and leave out the pairs it is part of, so every other problem shows too.
    values = []
    for text in typed:
        try:
            values.append(float(text))
        except ValueError:
            values.append(text)
    try:
        return config_store.check_request({}, joint, settings.NAMES, values)
    except config_store.InvalidSetting as error:
        raise EntryError([(named_fields(problem), shown(joint, problem))
                          for problem in error.problems]) from None


def shown(joint, problem):
    """Return a problem of joint as the operator reads it beside the field: without 'joint N '."""
    prefix = 'joint %d ' % joint
    return problem[len(prefix):] if problem.startswith(prefix) else problem


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
        raise EntryError([((), 'setpoint: %r is not a number' % text.strip())]) from None
    if not math.isfinite(angle_rad):
        raise EntryError([((), 'setpoint: %r is not a finite number' % text.strip())])
    if stored is not None and not stored['angle_min'] <= angle_rad <= stored['angle_max']:
        raise EntryError([((), 'setpoint: %s rad is outside the angle limits [%s, %s]' % (
            field_text(angle_rad), field_text(stored['angle_min']),
            field_text(stored['angle_max'])))])
    return angle_rad
