"""Checks of the cameras' image parameters, shared by the webcam, the republisher and the
simulated cameras (pure, and without OpenCV, which the simulated cameras load only when watched).
"""
SIZE_RANGE = (16, 4096)    # pixels, each side
QUALITY_RANGE = (1, 100)   # OpenCV's (and libjpeg's) JPEG quality scale


def whole(name, value, low, high, unit=''):
    """Return a parameter's value as an int in low..high.

    Raises:
        ValueError: not a whole number in that range (bools are refused: `true` is a typo).
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value) \
            or not low <= value <= high:
        raise ValueError('~%s must be a whole number%s in %d..%d, got %r'
                         % (name, unit, low, high, value))
    return int(value)


def pixels(name, value):
    """Return an image side (~width, ~height) in pixels (ValueError: out of SIZE_RANGE)."""
    return whole(name, value, *SIZE_RANGE, unit=' of pixels')


def quality(value):
    """Return a JPEG quality (~quality) in QUALITY_RANGE (ValueError: it is not one)."""
    return whole('quality', value, *QUALITY_RANGE)
