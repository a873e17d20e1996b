"""Checks of the nodes' numeric ROS parameters (pure: the value is passed in)."""
import math


def positive(name, value, minimum=0.0):
    """Return a parameter's value as a finite float above 0 and at least `minimum` (if not 0).

    A bool is refused although Python counts it as a number (`true` in a launch file is a typo).

    Raises:
        ValueError: the value is not such a number (the message names the parameter).
    """
    try:
        number = math.nan if isinstance(value, bool) else float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (math.isfinite(number) and number > 0.0 and number >= minimum):
        raise ValueError('%s must be a number of at least %g, got %r' % (name, minimum, value)
                         if minimum else '%s must be a positive number, got %r' % (name, value))
    return number
