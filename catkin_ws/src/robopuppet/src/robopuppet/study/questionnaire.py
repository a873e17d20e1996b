"""The questionnaire after each device: NASA-TLX (raw, unweighted) and the System Usability Scale.

The order of TLX_SCALES and SUS_ITEMS is the order of robopuppet_msgs/Questionnaire's tlx and sus
arrays. Pure: no ROS, no Qt.
"""
import collections
import math

TLX_MIN, TLX_MAX, TLX_STEP = 0, 100, 5   # a TLX rating's range and the step the GUI offers
SUS_MIN, SUS_MAX = 1, 5                  # a SUS answer: 1 strongly disagree .. 5 strongly agree

Scale = collections.namedtuple('Scale', 'name question low high')
Scale.__doc__ = """One NASA-TLX scale: its name, the question it asks, and what its low (0) and
high (100) ends mean."""

TLX_SCALES = (
    Scale('Mental demand', 'How much thinking, deciding and remembering did the task ask of you?',
          'very low', 'very high'),
    Scale('Physical demand', 'How much bodily effort (moving, reaching, pressing) did it take?',
          'very low', 'very high'),
    Scale('Temporal demand', 'How rushed did you feel by the pace of the task?',
          'very low', 'very high'),
    Scale('Performance', 'How well did you do what you were asked to do?',
          'perfect', 'failure'),   # reversed on purpose, as in the instrument: high = worse
    Scale('Effort', 'How hard did you have to work, in mind and body, for your result?',
          'very low', 'very high'),
    Scale('Frustration', 'How irritated, stressed or discouraged did you feel?',
          'very low', 'very high'),
)

# The ten statements of the System Usability Scale, in their standard order and wording.
SUS_ITEMS = (
    'I think that I would like to use this system frequently.',
    'I found the system unnecessarily complex.',
    'I thought the system was easy to use.',
    'I think that I would need the support of a technical person to be able to use this '
    'system.',
    'I found the various functions in this system were well integrated.',
    'I thought there was too much inconsistency in this system.',
    'I would imagine that most people would learn to use this system very quickly.',
    'I found the system very cumbersome to use.',
    'I felt very confident using the system.',
    'I needed to learn a lot of things before I could get going with this system.',
)
SUS_ANCHORS = ('strongly disagree', 'disagree', 'neutral', 'agree', 'strongly agree')


def tlx_raw(ratings):
    """Return the raw TLX workload (0..100): the mean of the six ratings.

    Raises:
        ValueError: the ratings are not valid (check_answers says why).
    """
    why = _check_tlx(ratings)
    if why:
        raise ValueError(why)
    return sum(float(r) for r in ratings) / len(TLX_SCALES)


def sus_score(answers):
    """Return the SUS score (0..100) of ten answers 1..5.

    Odd-numbered statements (1, 3, ...) are worded positively and count answer - 1; even ones
    negatively and count 5 - answer; the sum (0..40) times 2.5.

    Raises:
        ValueError: the answers are not valid (check_answers says why).
    """
    why = _check_sus(answers)
    if why:
        raise ValueError(why)
    total = sum(a - 1 if number % 2 else 5 - a for number, a in enumerate(answers, 1))
    return 2.5 * total


def check_answers(tlx, sus):
    """Return '' when tlx (6 ratings 0..100) and sus (10 answers 1..5) are complete and valid,
    else why not, for the participant (e.g. 'SUS statement 4 is not answered')."""
    return _check_tlx(tlx) or _check_sus(sus)


def _check_tlx(ratings):
    ratings = list(ratings)
    if len(ratings) != len(TLX_SCALES):
        return 'NASA-TLX needs %d ratings, got %d' % (len(TLX_SCALES), len(ratings))
    for scale, rating in zip(TLX_SCALES, ratings):
        if rating is None:
            return '%s is not rated' % scale.name
        if (not isinstance(rating, (int, float)) or not math.isfinite(rating)
                or not TLX_MIN <= rating <= TLX_MAX):
            return '%s must be rated %d..%d, got %r' % (scale.name, TLX_MIN, TLX_MAX, rating)
    return ''


def _check_sus(answers):
    answers = list(answers)
    if len(answers) != len(SUS_ITEMS):
        return 'SUS needs %d answers, got %d' % (len(SUS_ITEMS), len(answers))
    for number, answer in enumerate(answers, 1):
        if answer is None:
            return 'SUS statement %d is not answered' % number
        if isinstance(answer, bool) or answer not in range(SUS_MIN, SUS_MAX + 1):
            return 'SUS statement %d must be answered %d..%d, got %r' % (
                number, SUS_MIN, SUS_MAX, answer)
    return ''
