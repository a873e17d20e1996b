"""A request to the config node (one joint, or several: a calibration): checked together, stored
all or none, written once, counted."""
import errno
import os

import pytest

from robopuppet import atomic_file, settings
from robopuppet.config import config_file, config_store
from robopuppet.config.settings_keeper import SettingsKeeper, check_arm_request

PATH = '/nowhere/arm_R.ini'
F32 = config_store.to_float32


def stored_joint():
    return config_store.defaults()[2]


@pytest.mark.parametrize('names, values', [
    (['angle_min', 'angle_max'], [2.0, 3.0]),     # a new minimum above the stored maximum
    (['angle_max', 'angle_min'], [3.0, 2.0]),     # the same in the other order
    (['angle_min', 'angle_max'], [-3.0, -2.0]),   # a new maximum below the stored minimum
    (['voltage_min', 'voltage_max'], [1.0, 1.0]),  # equal is allowed
])
def test_a_minimum_and_its_maximum_are_checked_after_the_whole_request(names, values):
    result = config_store.check_request(stored_joint(), 2, names, values)
    assert [result[name] for name in names] == [F32(v) for v in values]


@pytest.mark.parametrize('names, values, problem', [
    (['angle_min', 'angle_max'], [1.0, 0.5], 'joint 2 angle_min = 1.0: above angle_max = 0.5'),
    (['angle_max'], [-2.0], 'joint 2 angle_max = -2.0: below angle_min = -1.571'),
    (['angle_min'], [1.6], 'joint 2 angle_min = 1.6: above angle_max = 1.571'),
    (['pid_kp', 'pid_kp'], [1.0, 2.0], 'joint 2 pid_kp = 2.0: pid_kp is named twice'),
    (['pid_kp'], [1.0, 2.0], 'joint 2: 1 setting names but 2 values'),
    (['pid_kp', 'pid_kq'], [1.0, 2.0], "joint 2: unknown setting 'pid_kq'"),
])
def test_a_request_is_refused_naming_why(names, values, problem):
    with pytest.raises(config_store.InvalidSetting) as error:
        config_store.check_request(stored_joint(), 2, names, values)
    assert error.value.problems == (problem,)


def test_every_problem_of_a_request_is_named_and_a_bad_value_hides_no_other():
    with pytest.raises(config_store.InvalidSetting) as error:
        config_store.check_request(stored_joint(), 2,
                                   ['pid_kp', 'sign_motor', 'voltage_min', 'voltage_max',
                                    'angle_min'],
                                   [float('nan'), 0.5, 5.0, 4.0, 9.0])
    problems = error.value.problems
    assert [p.split(':')[0] for p in problems] == [
        'joint 2 pid_kp = nan', 'joint 2 sign_motor = 0.5', 'joint 2 angle_min = 9.0',
        'joint 2 voltage_min = 5.0']
    assert 'outside its bound' in problems[2] and 'above voltage_max = 4' in problems[3]
    assert str(error.value) == '; '.join(problems)


class FakeFile:
    """The ini file as write sees it: the texts written, or an OSError to raise."""

    def __init__(self):
        self.writes = []
        self.error = None

    def write(self, path, text):
        assert path == PATH
        if self.error:
            raise self.error
        self.writes.append(text)


def keeper(unwritable=''):
    disk = FakeFile()
    text = config_store.default_text()
    config, _ = config_store.parse(text)
    return SettingsKeeper(config, text, unwritable, PATH, disk.write), disk


def test_a_good_request_is_written_once_counted_and_served():
    store, disk = keeper()
    answer = store.request(3, ['angle_min', 'angle_max', 'pid_kd'], [2.0, 2.5, 0.25])
    assert answer.stored and answer.written and answer.error == ''
    assert answer.values == dict(config_store.defaults()[3], angle_min=2.0, angle_max=2.5,
                                 pid_kd=0.25)
    assert store.joint(3) == answer.values and store.revision == 1
    assert len(disk.writes) == 1
    on_disk, problems = config_store.parse(disk.writes[0])
    assert problems == [] and on_disk[3] == answer.values
    assert on_disk[4] == config_store.defaults()[4]
    changed = [line for line in disk.writes[0].splitlines()
               if line not in config_store.default_text().splitlines()]
    assert changed == ['angle_min = 2', 'angle_max = 2.5', 'pid_kd = 0.25']
    revision, joints = store.all_joints()
    assert revision == 1 and joints[3] == answer.values and len(joints) == settings.NUM_JOINTS


def test_a_request_equal_to_what_is_stored_is_stored_without_a_write():
    store, disk = keeper()
    answer = store.request(1, ['pid_kp', 'sign_angle'], [0.0, 1.0])
    assert answer.stored and not answer.written and answer.error == ''
    assert disk.writes == [] and store.revision == 0


@pytest.mark.parametrize('joint, names, values, words', [
    (1, ['pid_kp', 'sign_motor'], [2.0, 0.5], 'sign must be'),
    (1, ['angle_min', 'pid_kp'], [1.6, 2.0], 'above angle_max'),
    (1, ['pid_kp'], [], '1 setting names but 0 values'),
    (9, ['pid_kp'], [2.0], 'valid joints are 0-6'),
])
def test_a_refused_request_changes_nothing_and_says_why(joint, names, values, words):
    store, disk = keeper()
    answer = store.request(joint, names, values)
    assert not answer.stored and not answer.written and not answer.persistence
    assert words in answer.error
    assert answer.values == (None if joint == 9 else config_store.defaults()[joint])
    assert store.joint(1)['pid_kp'] == 0.0, 'the good value of a refused request is not kept'
    assert disk.writes == [] and store.revision == 0


def test_an_unwritable_file_refuses_every_request_with_its_reason():
    store, disk = keeper(unwritable='cannot repair /nowhere/arm_R.ini: Read-only file system')
    answer = store.request(0, ['pid_kp'], [1.0])
    assert not answer.stored and answer.persistence
    assert answer.error == ('changes will not persist (cannot repair /nowhere/arm_R.ini: '
                            'Read-only file system)')
    assert answer.values == config_store.defaults()[0]
    assert disk.writes == [] and store.revision == 0


def test_a_failed_write_changes_nothing_and_the_next_good_request_starts_from_the_old_text():
    store, disk = keeper()
    disk.error = OSError(errno.ENOSPC, 'No space left on device')
    answer = store.request(0, ['pid_kp'], [1.0])
    assert not answer.stored and answer.persistence
    assert 'could not save it to %s' % PATH in answer.error and 'No space left' in answer.error
    assert store.joint(0)['pid_kp'] == 0.0 and store.revision == 0
    disk.error = None
    answer = store.request(0, ['pid_ki'], [0.5])
    assert answer.stored and store.revision == 1
    on_disk, _ = config_store.parse(disk.writes[0])
    assert on_disk[0]['pid_kp'] == 0.0 and on_disk[0]['pid_ki'] == 0.5


FROZEN = "Baxter's right arm follows this puppet: stop following first: press 3"


@pytest.mark.parametrize('name, value', [
    ('home_angle', 0.5), ('sign_angle', -1.0), ('angle_min', -1.0), ('angle_max', 1.0),
    ('velocity_min', -1.0), ('velocity_max', 1.0)])
def test_a_change_of_what_the_angles_mean_is_refused_while_an_arm_follows(name, value):
    store, disk = keeper()
    answer = store.request(2, ['pid_kp', name], [1.0, value], frozen=FROZEN)
    assert not answer.stored and not answer.written and not answer.persistence
    assert answer.error == "joint 2 %s changes what the puppet's angles mean, and %s" % (
        name, FROZEN)
    assert answer.values == config_store.defaults()[2]   # pid_kp not stored either: all or none
    assert disk.writes == [] and store.revision == 0
    assert store.request(2, [name], [value]).stored   # once nothing follows


def test_while_an_arm_follows_other_settings_and_unchanged_values_are_stored():
    store, disk = keeper()
    names = [n for n in settings.NAMES if n not in settings.ANGLE_SETTINGS]
    values = [-2.0, 2.0, 3.0, 0.1, 0.2, -1.0]
    assert names == ['voltage_min', 'voltage_max', 'pid_kp', 'pid_ki', 'pid_kd', 'sign_motor']
    answer = store.request(4, names + ['home_angle', 'sign_angle'], values + [0.0, 1.0],
                           frozen=FROZEN)
    assert answer.stored and answer.written and store.revision == 1
    answer = store.request(4, ['home_angle', 'sign_angle'], [0.5, -1.0], frozen=FROZEN)
    assert answer.error.startswith('joint 4 home_angle and sign_angle change what')


# A calibration: every joint's home_angle and sign_angle in one request.
CALIBRATION = [(joint, ['home_angle', 'sign_angle'], [0.1 * joint, -1.0])
               for joint in settings.JOINTS]


def file_keeper(tmp_path):
    """A keeper of a real ini file written by atomic_file.write_atomic; return it and the path."""
    path = str(tmp_path / 'arm_R.ini')
    loaded = config_file.load_or_create(path, '', 'stamp')
    assert loaded.unwritable == '' and loaded.problems == []
    return SettingsKeeper(loaded.config, loaded.text, '', path, atomic_file.write_atomic), path


def test_one_bad_value_in_joint_5_of_an_arm_request_writes_nothing(tmp_path):
    store, path = file_keeper(tmp_path)
    before = open(path, 'rb').read()
    changes = list(CALIBRATION)
    changes[5] = (5, ['home_angle', 'sign_angle'], [0.5, 0.5])   # not a sign
    answer = store.request_arm(changes)
    assert not answer.stored and not answer.written and not answer.persistence
    assert answer.error == 'joint 5 sign_angle = 0.5: a sign must be +1 or -1'
    assert answer.values == [config_store.defaults()[j] for j in settings.JOINTS]
    assert open(path, 'rb').read() == before, 'the ini is byte-identical'
    assert sorted(os.listdir(str(tmp_path))) == ['arm_R.ini'], 'no temporary left'
    assert store.revision == 0 and store.all_joints()[1] == answer.values


def test_an_arm_request_is_written_with_one_replace_and_counts_one_revision(tmp_path):
    store, path = file_keeper(tmp_path)
    writes = []
    store._write = lambda p, text: writes.append(text) or atomic_file.write_atomic(p, text)
    answer = store.request_arm(CALIBRATION)
    assert answer.stored and answer.written and answer.error == ''
    assert len(writes) == 1 and store.revision == 1
    with open(path) as ini:
        on_disk, problems = config_store.parse(ini.read())
    assert problems == []
    for joint in settings.JOINTS:
        wanted = dict(config_store.defaults()[joint], home_angle=F32(0.1 * joint),
                      sign_angle=-1.0)
        assert on_disk[joint] == wanted == answer.values[joint] == store.joint(joint)
    assert store.request_arm(CALIBRATION) == (True, '', answer.values, False, False), \
        'the same calibration again: stored, nothing written'
    assert len(writes) == 1 and store.revision == 1


@pytest.mark.parametrize('changes, problems', [
    ([(2, ['pid_kp'], [1.0]), (2, ['pid_ki'], [1.0])],
     ('joint 2 is named twice in one request',)),
    ([(1, ['pid_kp'], [1.0]), (9, ['pid_kp'], [1.0])],
     ('joint 9 does not exist: valid joints are 0-6',)),
    ([(0, ['angle_min'], [2.0]), (6, ['pid_kq', 'sign_motor'], [1.0, 0.0])],
     ('joint 0 angle_min = 2.0: above angle_max = 1.571', "joint 6: unknown setting 'pid_kq'",
      'joint 6 sign_motor = 0.0: a sign must be +1 or -1')),
])
def test_an_arm_request_names_every_problem_of_every_joint(changes, problems):
    with pytest.raises(config_store.InvalidSetting) as error:
        check_arm_request(config_store.defaults(), changes)
    assert error.value.problems == problems
    store, disk = keeper()
    assert store.request_arm(changes).error == '; '.join(problems)
    assert disk.writes == [] and store.revision == 0


def test_a_calibration_is_refused_whole_while_an_arm_follows():
    store, disk = keeper()
    changes = [(0, ['home_angle', 'pid_kp'], [0.5, 1.0]), (3, ['pid_kd'], [0.5]),
               (4, ['sign_angle', 'home_angle'], [-1.0, 0.0])]   # joint 4's home unchanged
    answer = store.request_arm(changes, frozen=FROZEN)
    assert not answer.stored and not answer.written and not answer.persistence
    assert answer.error == ("joint 0 home_angle, joint 4 sign_angle change what the puppet's "
                            'angles mean, and ' + FROZEN)
    assert disk.writes == [] and store.revision == 0
    assert store.request_arm([(0, ['pid_kp'], [1.0]), (3, ['pid_kd'], [0.5])],
                             frozen=FROZEN).written, 'other settings may change'
    assert store.request_arm(changes).written and store.revision == 2


def test_an_arm_request_to_an_unwritable_or_failing_file_changes_nothing():
    store, disk = keeper(unwritable='cannot repair /nowhere/arm_R.ini: Read-only file system')
    answer = store.request_arm(CALIBRATION)
    assert not answer.stored and answer.persistence and 'will not persist' in answer.error
    store, disk = keeper()
    disk.error = OSError(errno.ENOSPC, 'No space left on device')
    answer = store.request_arm(CALIBRATION)
    assert not answer.stored and answer.persistence and 'No space left' in answer.error
    assert store.all_joints() == (0, [config_store.defaults()[j] for j in settings.JOINTS])
