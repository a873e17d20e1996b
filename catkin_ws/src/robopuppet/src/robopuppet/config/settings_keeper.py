"""One arm's stored joint settings: requests of one or several joints, all or none; a revision.

Pure: no ROS, no clock; the file is written only through the `write` callable it is given (the
node passes atomic_file.write_atomic). Not thread-safe: the caller serialises requests.
"""
import collections

from robopuppet import settings
from robopuppet.config import config_store

Answer = collections.namedtuple('Answer', 'stored error values written persistence')
Answer.__doc__ = """What SettingsKeeper.request or request_arm did.

    stored: True when the joints now hold the requested values (written, or already stored).
    error: '' when stored, else why nothing changed.
    values: request's: the joint's {name: value} stored now (after the request), or None for a
        joint that does not exist; request_arm's: [{name: value} of joint 0, ..., joint 6].
    written: True when the file was written and the revision went up.
    persistence: True when the request was refused because it could not persist (the file is
        unwritable, or the write failed), not because of its values.
"""


def check_arm_request(config, changes):
    """Return config with several joints' settings changed, every joint checked: all or none.

    Args:
        config: the stored {joint: {name: value}}.
        changes: [(joint, names, values)], each joint at most once (config_store.check_request's
            arguments).
    Raises:
        config_store.InvalidSetting: every problem of every joint (check_request's), and a
            joint named twice.
    """
    result = {joint: dict(values) for joint, values in config.items()}
    errors, seen = [], set()
    for joint, names, values in changes:
        if joint in seen:
            errors.append('joint %r is named twice in one request' % (joint,))
            continue
        seen.add(joint)
        try:
            result[joint] = config_store.check_request(config.get(joint, {}), joint, names,
                                                       values)
        except config_store.InvalidSetting as error:
            errors.extend(error.problems)
    if errors:
        raise config_store.InvalidSetting(*errors)
    return result


def _frozen_error(meaning, frozen):
    """Say that [(joint, [angle setting names])] may not change now, and why (frozen)."""
    parts = ['joint %d %s' % (joint, ' and '.join(names)) for joint, names in meaning]
    many = len(meaning) > 1 or len(meaning[0][1]) > 1
    return "%s change%s what the puppet's angles mean, and %s" % (
        ', '.join(parts), '' if many else 's', frozen)


class SettingsKeeper:
    """Hold the stored settings of one arm and change them only when the file takes the change.

    Args:
        config: {joint: {name: float32 value}}, complete (config_file.load_or_create's).
        text: the ini text on disk, which edits start from (comments and layout are kept).
        unwritable: '' when the file may be written; else why not, and every request is refused
            with that reason.
        path: the ini file, named in messages and passed to write.
        write: write(path, text), raising OSError when the file cannot be written (the old file
            must then be unchanged).
    """

    def __init__(self, config, text, unwritable, path, write):
        self._config = {joint: dict(values) for joint, values in config.items()}
        self._text = text
        self._unwritable = unwritable
        self._path = path
        self._write = write
        self._revision = 0

    @property
    def revision(self):
        """The number of changes written since the start (0: the settings as loaded)."""
        return self._revision

    def joint(self, joint):
        """Return a copy of a joint's {name: value}.

        Raises:
            config_store.InvalidSetting: joint is not 0..6.
        """
        config_store.check_joint(joint)
        return dict(self._config[joint])

    def all_joints(self):
        """Return (revision, [{name: value} of joint 0, ..., joint 6]), copies."""
        return self._revision, [dict(self._config[j]) for j in sorted(self._config)]

    def request(self, joint, names, values, frozen=''):
        """Store values[i] as setting names[i] of a joint, all of them or none; return an Answer.

        As request_arm with one joint; the Answer's values are that joint's (None for a joint
        outside 0..6).
        """
        try:
            self.joint(joint)
        except config_store.InvalidSetting as error:
            return Answer(False, str(error), None, False, False)
        answer = self.request_arm([(joint, names, values)], frozen)
        return answer._replace(values=answer.values[joint])

    def request_arm(self, changes, frozen=''):
        """Store several joints' settings in one request, all or none; return an Answer.

        changes: [(joint, names, values)], each joint at most once. Refused, changing nothing:
        while the file is unwritable; a request that check_arm_request refuses (one bad value
        of any joint refuses every joint); a change of a setting of settings.ANGLE_SETTINGS
        while `frozen` says why they may not change (follow_lock: a Baxter arm follows); a
        write that fails. A request equal to what is stored is stored=True without a write.
        Otherwise only the option lines of the settings that change are rewritten in the text,
        the file is written once (one atomic replace) and the revision goes up by one.
        """
        old = self.all_joints()[1]
        if self._unwritable:
            return Answer(False, 'changes will not persist (%s)' % self._unwritable, old, False,
                          True)
        try:
            config = check_arm_request(self._config, changes)
        except config_store.InvalidSetting as error:
            return Answer(False, str(error), old, False, False)
        changed = {(joint, name) for joint in config for name in config[joint]
                   if config[joint][name] != self._config[joint][name]}
        if not changed:
            return Answer(True, '', old, False, False)
        meaning = [(joint, [n for n in settings.ANGLE_SETTINGS if (joint, n) in changed])
                   for joint in sorted(config)]
        meaning = [(joint, names) for joint, names in meaning if names]
        if frozen and meaning:
            return Answer(False, _frozen_error(meaning, frozen), old, False, False)
        text = config_store.render(self._text, config, only=changed)
        try:
            self._write(self._path, text)
        except OSError as error:
            return Answer(False, 'could not save it to %s (%s), so it would not persist'
                          % (self._path, error), old, False, True)
        self._config, self._text = config, text
        self._revision += 1
        return Answer(True, '', self.all_joints()[1], True, False)
