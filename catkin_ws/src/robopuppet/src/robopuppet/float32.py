"""The settings' numbers as the wire carries them: float32 rounding and its shortest text."""
import math
import struct


def to_float32(value):
    """Return value rounded to float32, as the wire and GetConfig carry it (inf if too large)."""
    try:
        return struct.unpack('<f', struct.pack('<f', value))[0]
    except OverflowError:
        return math.copysign(math.inf, value)


def format_value(value):
    """Return the shortest plain decimal text that reads back as the same float32 ('0.1', '10')."""
    target = struct.pack('<f', value)
    for digits in range(1, 18):
        number = float('%.*g' % (digits, value))
        if struct.pack('<f', number) == target:
            text = repr(number)  # plain notation where Python uses it: 10.0, not 1e+01
            return text[:-2] if text.endswith('.0') else text
    return repr(value)
