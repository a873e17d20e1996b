"""One arm's stored joint settings: requests applied all or none, the ini text, a revision.

Pure: no ROS, no clock; the file is written only through the `write` callable it is given (the
node passes config_file.write_atomic). Not thread-safe: the caller serialises requests.
"""
import collections

from robopuppet import settings
from robopuppet.config import config_store

Answer = collections.namedtuple('Answer', 'stored error values written persistence')
Answer.__doc__ = """What SettingsKeeper.request did.

    stored: True when the joint now holds the requested values (written, or already stored).
    error: '' when stored, else why nothing changed.
    values: the joint's {name: value} stored now (after the request), or None for a joint
        that does not exist.
    written: True when the file was written and the revision went up.
    persistence: True when the request was refused because it could not persist (the file is
        unwritable, or the write failed), not because of its values.
"""


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

        Refused, changing nothing: while the file is unwritable; a request that
        config_store.check_request refuses; a change of a setting of settings.ANGLE_SETTINGS
        while `frozen` says why they may not change (follow_lock: a Baxter arm follows); a
        write that fails. A request equal to what is
        stored is stored=True without a write. Otherwise only the option lines of the settings
        that change are rewritten in the text, the file is written and the revision goes up.
        """
        try:
            old = self.joint(joint)
        except config_store.InvalidSetting as error:
            return Answer(False, str(error), None, False, False)
        if self._unwritable:
            return Answer(False, 'changes will not persist (%s)' % self._unwritable, old, False,
                          True)
        try:
            new = config_store.check_request(old, joint, names, values)
        except config_store.InvalidSetting as error:
            return Answer(False, str(error), old, False, False)
        changed = {(joint, name) for name in new if new[name] != old[name]}
        if not changed:
            return Answer(True, '', old, False, False)
        meaning = [name for name in settings.ANGLE_SETTINGS if (joint, name) in changed]
        if frozen and meaning:
            return Answer(False, "joint %d %s change%s what the puppet's angles mean, and %s"
                          % (joint, ' and '.join(meaning), '' if len(meaning) > 1 else 's',
                             frozen), old, False, False)
        config = dict(self._config)
        config[joint] = new
        text = config_store.render(self._text, config, only=changed)
        try:
            self._write(self._path, text)
        except OSError as error:
            return Answer(False, 'could not save it to %s (%s), so it would not persist'
                          % (self._path, error), old, False, True)
        self._config, self._text = config, text
        self._revision += 1
        return Answer(True, '', dict(new), True, False)
