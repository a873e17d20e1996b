"""Joint settings of one puppet arm: validation, ini parsing and comment-preserving edits.

Pure: no file or ROS access. The ini text is `[joint_0]` ... `[joint_6]`, each with the twelve
options of settings.SETTINGS as `name = value`, and `[feel]` with settings.FEEL_SETTINGS (feel
mode's gentle gains; a file without it reads as the defaults and gets it on its next write).
Lines starting with '#' or ';' are comments, and a value may carry an inline comment after
whitespace ('angle_min = -1.2  ; soft stop').
"""
import re

from robopuppet import settings
from robopuppet.config import feel_profile
from robopuppet.float32 import format_value, to_float32

_SECTION_RE = re.compile(r'^\s*\[\s*([^\]]*?)\s*\]\s*$')
_OPTION_RE = re.compile(r'^(\s*)([A-Za-z_]\w*)(\s*[=:]\s*)(.*?)(\s+[#;].*)?\s*$')
_COMMENT_RE = re.compile(r'^\s*([#;].*)?$')
FEEL = settings.FEEL_SECTION  # the [feel] section's key where a joint's index would be


class InvalidSetting(ValueError):
    """Setting values that the puppet must not receive; each problem names joint, setting, value.

    str() is the problems joined by '; '; .problems is the tuple of them.
    """

    def __init__(self, *problems):
        super().__init__('; '.join(problems))
        self.problems = problems


def defaults():
    """Return a fresh config: {joint: {name: default value}} for all seven joints."""
    return {joint: {name: to_float32(value) for name, value in settings.DEFAULTS.items()}
            for joint in settings.JOINTS}


def check_joint(joint):
    """Raise InvalidSetting unless joint is a valid joint index (0..6)."""
    if not isinstance(joint, int) or joint not in settings.JOINTS:
        raise InvalidSetting('joint %r does not exist: valid joints are %d-%d'
                             % (joint, settings.JOINTS[0], settings.JOINTS[-1]))


def check_request(joint_values, joint, names, values):
    """Return a joint's settings with some of them changed, checked together: all or none.

    Args:
        joint_values: the joint's stored {name: value}; the settings not named keep these.
        joint: joint index 0..6.
        names: setting names from settings.NAMES, each at most once.
        values: one value per name, in the setting's unit (settings.SETTINGS).
    Returns:
        A new {name: float32 value} of all twelve settings.
    Raises:
        InvalidSetting: every problem (each names joint, setting and value): a joint outside
            0..6, names and values of different lengths, an unknown or repeated name, a value
            that is not a number or not finite, a sign not +-1, a value outside its bound, a
            range that breaks its rule once all values of the request are applied
            (settings.range_problems).
    """
    check_joint(joint)
    if len(names) != len(values):
        raise InvalidSetting('joint %d: %d setting names but %d values'
                             % (joint, len(names), len(values)))
    result = dict(joint_values)
    requested, refused, errors = {}, set(), []
    for name, value in zip(names, values):
        where = 'joint %d %s = %r' % (joint, name, value)
        if name not in settings.CONFIG_ID:
            errors.append('joint %d: unknown setting %r' % (joint, name))
            continue
        if name in requested:
            errors.append('%s: %s is named twice' % (where, name))
            refused.add(name)
            continue
        requested[name] = value
        try:
            result[name] = to_float32(float(value))
            reason = settings.implausible(name, result[name])
        except (TypeError, ValueError):
            reason = 'not a number'
        if reason:
            errors.append('%s: %s' % (where, reason))
            refused.add(name)
    errors += ['joint %d %s' % (joint, why)
               for _, _, why in settings.range_problems(result, requested, refused)]
    if errors:
        raise InvalidSetting(*errors)
    return result


def _lines(text):
    """Yield (index, kind, match) for each line: kind is section, option, comment or junk."""
    for index, line in enumerate(text.splitlines()):
        for kind, regex in (('comment', _COMMENT_RE), ('section', _SECTION_RE),
                            ('option', _OPTION_RE)):
            match = regex.match(line)
            if match:
                yield index, kind, match
                break
        else:
            yield index, 'junk', None


def _entries(text):
    """Yield (index, kind, match, joint, problem) for each line of an ini text.

    joint is the joint whose value a section or option line holds (FEEL in [feel]), or None
    when the line is ignored: an unknown section, a repeated [joint_N] section and everything
    in it, a repeated or unknown option. The first occurrence always wins, for reading and for
    writing alike. problem says why a line is ignored, or is None.
    """
    known_sections = {settings.section(j): j for j in settings.JOINTS}
    known_sections[FEEL] = FEEL
    seen_sections, seen_options = set(), set()
    joint, section = None, None
    for index, kind, match in _lines(text):
        problem = None
        if kind == 'section':
            section = match.group(1)
            joint = known_sections.get(section)
            if joint is None:
                problem = 'line %d: unknown section [%s] ignored' % (index + 1, section)
            elif joint in seen_sections:
                problem = 'line %d: repeated section [%s] ignored' % (index + 1, section)
                joint = None
            else:
                seen_sections.add(joint)
            yield index, kind, match, joint, problem
            continue
        if kind == 'option':
            name = match.group(2)
            if section is None:
                problem = 'line %d: option outside any section ignored' % (index + 1)
            elif joint is None:
                pass  # inside an ignored section, which is reported already
            elif name not in _names(joint):
                problem = '[%s] %s: unknown option ignored' % (section, name)
            elif (joint, name) in seen_options:
                problem = 'line %d: repeated option %s in [%s] ignored' % (index + 1, name,
                                                                          section)
            else:
                seen_options.add((joint, name))
                yield index, kind, match, joint, None
                continue
            yield index, kind, match, None, problem
            continue
        if kind == 'junk':
            problem = 'line %d: not an ini line, ignored' % (index + 1)
        yield index, kind, match, None, problem


def parse(text):
    """Read an arm's ini text, repairing what is missing or broken with defaults.

    Returns:
        (config, problems): config is {joint: {name: float}} for all joints and settings;
        problems is a list of human-readable strings, one per entry that was repaired or
        ignored (empty when the text was complete and valid).
    """
    config = defaults()
    problems = []
    raw = {}  # (joint, name) -> text
    seen_sections = set()
    for index, kind, match, joint, problem in _entries(text):
        if problem:
            problems.append(problem)
        if kind == 'section' and joint is not None and joint != FEEL:
            seen_sections.add(settings.section(joint))
        elif kind == 'option' and joint is not None:
            raw[(joint, match.group(2))] = match.group(4)
    if not seen_sections:
        return config, ['not an ini file: no [joint_N] sections; using defaults']
    for joint in settings.JOINTS:
        sec = settings.section(joint)
        if sec not in seen_sections:
            problems.append('[%s] missing section: using defaults' % sec)
            continue
        for name in settings.NAMES:
            text_value = raw.get((joint, name))
            if text_value is None:
                problems.append('[%s] %s: missing, using default %s'
                                % (sec, name, format_value(settings.DEFAULTS[name])))
                continue
            try:
                number = to_float32(float(text_value))
            except ValueError:
                problems.append('[%s] %s = %r: not a number, using default %s'
                                % (sec, name, text_value, format_value(settings.DEFAULTS[name])))
                continue
            reason = settings.implausible(name, number)
            if reason:
                problems.append('[%s] %s = %s: invalid (%s), using default %s'
                                % (sec, name, text_value, reason,
                                   format_value(settings.DEFAULTS[name])))
                continue
            config[joint][name] = number
        for low, high, why in settings.range_problems(config[joint], {}):
            problems.append('[%s] %s, using defaults for both' % (sec, why))
            for name in (low, high):
                config[joint][name] = to_float32(settings.DEFAULTS[name])
    return config, problems + feel_profile.feel_values(
        {name: text for (key, name), text in raw.items() if key == FEEL})[1]


def _names(key):
    """Return the option names of a joint's section, or of [feel] for key FEEL."""
    return settings.FEEL_NAMES if key == FEEL else settings.CONFIG_ID


def parse_feel(text):
    """Return ({name: value} of the [feel] section, problems) (see feel_profile.feel_values);
    parse reports the same problems among the file's others."""
    raw = {match.group(2): match.group(4) for _, kind, match, key, _ in _entries(text)
           if kind == 'option' and key == FEEL}
    return feel_profile.feel_values(raw)


def render(text, config, only=None):
    """Return `text` with the values of `config` written in, keeping comments and layout.

    Every line that parse ignores is dropped, so that the result parses without problems:
    torn and other non-ini lines, unknown and repeated sections with what they hold (comments
    included), repeated and unknown options, options outside any section.

    The [feel] section is written with parse_feel's values of `text` (a bad value repaired).

    Args:
        text: the current ini text (may be empty or not an ini at all).
        config: {joint: {name: value}}, complete for every joint and setting.
        only: optional set of (joint, name) to write; other option lines are left as they are.
            Missing options and sections (the [feel] section too) are always added.
    Returns:
        The new ini text, ending with a newline.
    """
    kinds = {kind for _, kind, _ in _lines(text)}
    if 'section' not in kinds and kinds - {'comment'}:
        text = ''  # not an ini: start afresh (the caller keeps a backup of the original)
    lines = text.splitlines()
    config = dict(config)
    config[FEEL] = parse_feel(text)[0]
    keep = [True] * len(lines)
    written = set()
    section_last = {}  # joint -> index of its section's last line that holds an option
    ignoring = False  # inside an ignored section
    for index, kind, match, joint, _ in _entries(text):
        if kind == 'section':
            ignoring = joint is None
        if kind == 'comment':
            keep[index] = not (ignoring and lines[index].strip())
            continue
        if joint is None:
            keep[index] = False
            continue
        section_last[joint] = index
        if kind == 'option':
            name = match.group(2)
            written.add((joint, name))
            if only is None or (joint, name) in only:
                lead, sep, comment = match.group(1), match.group(3), match.group(5) or ''
                lines[index] = '%s%s%s%s%s' % (lead, name, sep,
                                               format_value(config[joint][name]), comment)
    missing = {section_last[joint]: ['%s = %s' % (name, format_value(config[joint][name]))
                                     for name in _names(joint) if (joint, name) not in written]
               for joint in section_last}
    out = []
    for index, line in enumerate(lines):
        if keep[index]:
            out.append(line)
        out.extend(missing.get(index, ()))
    for joint in settings.JOINTS + (FEEL,):
        if joint not in section_last:
            if out and out[-1].strip():
                out.append('')
            out.extend(feel_profile.INTRO + ['[%s]' % FEEL] if joint == FEEL
                       else ['[%s]' % settings.section(joint)])
            out.extend('%s = %s' % (name, format_value(config[joint][name]))
                       for name in _names(joint))
    return '\n'.join(out) + '\n'


def default_text(header=''):
    """Return a complete ini text with the default settings and a comment per option kind."""
    intro = [header] if header else []
    intro += ['# RoboPuppet joint settings, one section per joint (see README.md).']
    intro += ['#   %-13s %-10s %s' % (s.name, s.unit, s.meaning) for s in settings.SETTINGS]
    return render('\n'.join(intro) + '\n', defaults())
