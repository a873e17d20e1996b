"""Seeded garbage of any ROS message type, built from the message class alone (imported by
test_topic_garbage.py).

MessageGarbage(seed).message(cls) walks cls's slots (_slot_types): numbers from the edges of
their type (NaN, +-inf, 1e39 where the type holds it, the integer range's ends), strings empty,
huge, random unicode or near-valid words, arrays of length 0, 1, 7, 8 or 1000, parallel arrays of
differing lengths, times and durations zero, huge or negative, nested messages the same way.
Every third message or so is plausible instead: the right joint names, parallel arrays of one
length, values in range, and one bad value in one place; those get past the first checks.
"""
import math
import random

import genpy
import roslib.message

from robopuppet import baxter_description, interface, settings

FLOAT64_BAD = (math.nan, math.inf, -math.inf, 1e39, -1e39, 1e308, -1e308, 5e-324, 0.0, -1.0)
# float32 cannot hold 1e39 or 5e-324 (rospy refuses to pack the first): its own edges instead.
FLOAT32_BAD = (math.nan, math.inf, -math.inf, 3.4e38, -3.4e38, 1.4e-45, 0.0, -1.0)
INT_RANGES = dict([('int%d' % bits, (-2 ** (bits - 1), 2 ** (bits - 1) - 1))
                   for bits in (8, 16, 32, 64)]
                  + [('uint%d' % bits, (0, 2 ** bits - 1)) for bits in (8, 16, 32, 64)],
                  byte=(-2 ** 7, 2 ** 7 - 1), char=(0, 2 ** 8 - 1))   # ROS 1's int8, uint8
LENGTHS = (0, 1, 7, 8, 1000)
HUGE_TEXT = 10 ** 5
# Characters and array items one message may hold: a DiagnosticArray of 1000 statuses of 1000
# values of 10^5 characters would not fit in memory; more would only slow the test down.
BUDGET = 3 * 10 ** 5
PLAUSIBLE_SHARE = 0.35


def _words():
    """Near-valid strings: every joint name the system knows, opmodes, states, their typos."""
    names = list(settings.JOINT_NAMES)
    for side in interface.BAXTER_SIDES:
        names += baxter_description.arm_joint_names(side)
        names += baxter_description.gripper_finger_joints(side)
    words = list(interface.OPMODES) + list(interface.TELEOP_STATES) + list(interface.ENC_STATUS)
    words += ['HOLD', 'Limp', 'feel ', 'left_s0', 'right_s9', 'joint_7', 'go', 'calibrate']
    return names, words + names


JOINT_NAMES, WORDS = _words()
NAME_LISTS = [list(settings.JOINT_NAMES)] + [baxter_description.arm_joint_names(s)
                                             for s in interface.BAXTER_SIDES]


class MessageGarbage:
    """A seeded source of garbage messages of any type."""

    def __init__(self, seed):
        self.rng = random.Random(seed)
        self._budget = BUDGET
        self._plausible = False
        self._names = NAME_LISTS[0]

    def message(self, msg_class):
        """Return a garbage instance of msg_class, now and then a plausible one (see above)."""
        self._budget = BUDGET
        self._plausible = self.rng.random() < PLAUSIBLE_SHARE
        self._names = self.rng.choice(NAME_LISTS)
        msg = self._fill(msg_class)
        if self._plausible:
            self._spoil_one(msg)
        return msg

    # The walk over slots.

    def _fill(self, msg_class):
        msg = msg_class()
        shared = self._length()   # parallel arrays: one length, or each its own
        for name, slot_type in zip(msg_class.__slots__, msg_class._slot_types):
            base, is_array, fixed = _array_info(slot_type)
            if is_array:
                if fixed is not None:
                    length = fixed
                elif self._plausible or self.rng.random() < 0.5:
                    length = shared
                else:
                    length = self._length()
                setattr(msg, name, self._array(base, length, name))
            else:
                setattr(msg, name, self._value(base, name))
        return msg

    def _length(self):
        if self._plausible:
            return len(self._names)
        return self.rng.choice(LENGTHS)

    def _array(self, base, length, field):
        length = min(length, max(0, self._budget // 16))
        self._budget -= 16 * length
        if base in ('uint8', 'char'):
            return bytes(self._value(base, field) for _ in range(length))
        if base == 'string' and self._plausible:
            return [self._names[i % len(self._names)] for i in range(length)]
        return [self._value(base, field) for _ in range(length)]

    def _value(self, base, field):
        rng = self.rng
        if base in ('float32', 'float64'):
            if self._plausible:
                return rng.uniform(-1.5, 1.5)
            bad = FLOAT32_BAD if base == 'float32' else FLOAT64_BAD
            return rng.choice(bad) if rng.random() < 0.7 else rng.uniform(-1e3, 1e3)
        if base in INT_RANGES:
            low, high = INT_RANGES[base]
            if self._plausible:
                return rng.randint(max(low, 0), min(high, 8))
            return rng.choice([low, high, 0, 1, max(low, -1), rng.randint(low, high),
                               rng.randint(max(low, 0), min(high, 10))])
        if base == 'bool':
            return rng.random() < 0.5
        if base == 'string':
            return self._text()
        if base in ('time', 'duration'):
            return self._stamp(base)
        return self._fill(roslib.message.get_message_class(base))

    def _text(self):
        rng = self.rng
        if self._plausible:
            return rng.choice(WORDS)
        choice = rng.randrange(5)
        if choice == 0:
            return ''
        if choice == 1 and self._budget > HUGE_TEXT:
            self._budget -= HUGE_TEXT
            return rng.choice('x\u00e9\u4e2d') * HUGE_TEXT
        if choice == 2:   # random unicode, no surrogates (not encodable as UTF-8)
            return ''.join(chr(rng.choice([rng.randrange(1, 0xd800),
                                           rng.randrange(0xe000, 0x110000)]))
                           for _ in range(rng.randrange(1, 40)))
        word = rng.choice(WORDS)
        return word if choice == 3 else word.upper() + rng.choice(['', ' ', '\0', '\n'])

    def _stamp(self, base):
        rng = self.rng
        if self._plausible:
            return (genpy.Time if base == 'time' else genpy.Duration)(rng.randrange(1, 10 ** 9))
        if base == 'time':   # genpy refuses negative times
            return genpy.Time(rng.choice([0, 2 ** 32 - 1, rng.randrange(2 ** 32)]),
                              rng.choice([0, 999999999]))
        return genpy.Duration(rng.choice([0, -2 ** 31, 2 ** 31 - 1, -1]),
                              rng.choice([0, 999999999]))

    # One bad value in a plausible message.

    def _spoil_one(self, msg):
        leaves = list(_leaves(msg))
        if not leaves:
            return
        owner, key, base = self.rng.choice(leaves)
        self._plausible = False
        value = self._value(base, key)
        if isinstance(owner, list):
            owner[key] = value
        else:
            setattr(owner, key, value)


def _array_info(slot_type):
    """Return (base type, is array, fixed length or None) of a slot type such as float64[7]."""
    if not slot_type.endswith(']'):
        return slot_type, False, None
    base, size = slot_type[:-1].split('[')
    return base, True, int(size) if size else None


def _leaves(msg):
    """Yield (owner, key, base type) of every number, string and stamp of msg, nested too:
    owner is the message (key the slot name) or the list (key the index)."""
    for name, slot_type in zip(msg.__slots__, msg._slot_types):
        base, is_array, _ = _array_info(slot_type)
        value = getattr(msg, name)
        if base in ('uint8', 'char') and is_array:
            continue   # bytes: immutable, and rarely where a bad value hides
        if not is_array:
            if hasattr(value, '__slots__') and base not in ('time', 'duration'):
                yield from _leaves(value)
            else:
                yield msg, name, base
            continue
        for index, item in enumerate(value):
            if hasattr(item, '_slot_types'):
                yield from _leaves(item)
            else:
                yield value, index, base
