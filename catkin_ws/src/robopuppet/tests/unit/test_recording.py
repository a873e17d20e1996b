"""Unit tests of the recorder's pure core: topics, button 4, names, metadata, disk rule, status."""
import math
import time

import pytest

from robopuppet import interface
from robopuppet.episodes import recording


@pytest.mark.parametrize('text, sides', [('R', ('R',)), ('LR', ('L', 'R')), ('r l', ('L', 'R')),
                                         ('L', ('L',))])
def test_sides_parse_in_interface_order(text, sides):
    assert recording.parse_sides(text) == sides


@pytest.mark.parametrize('text', ['', 'X', 'RX', 'left'])
def test_bad_sides_are_refused(text):
    with pytest.raises(ValueError):
        recording.parse_sides(text)


def test_an_episode_of_the_right_arm_holds_its_topics_and_baxters_not_the_left_arms():
    topics = recording.recorded_topics(('R',))
    assert len(topics) == len(set(topics))
    for name in ('joint_states', 'gripper_0', 'gripper_3', 'user_btn', 'opmode', 'teleop_state',
                 'stored_settings'):
        assert '/puppet/arm_R/' + name in topics
    assert not any(t.startswith('/puppet/arm_L') for t in topics)
    for side in ('left', 'right'):
        assert '/robot/limb/%s/joint_command' % side in topics
        assert '/robot/end_effector/%s_gripper/command' % side in topics
        assert '/robot/end_effector/%s_gripper/state' % side in topics
    assert {'/robot/joint_states', '/diagnostics'} <= set(topics)
    both = recording.recorded_topics(('L', 'R'))
    assert len(both) == len(topics) + len(recording.SIDE_TOPICS)


def test_cameras_add_their_compressed_images_and_only_the_buttons_stay_subscribed():
    cameras = ('room_camera', 'right_hand_camera')
    topics = recording.recorded_topics(('L', 'R'), cameras)
    assert topics[-2:] == ('/cameras/room_camera/image/compressed',
                           '/cameras/right_hand_camera/image/compressed')
    assert topics[:-2] == recording.recorded_topics(('L', 'R'))
    buttons = recording.button_topics(('L', 'R'))
    assert buttons == ('/puppet/arm_L/user_btn', '/puppet/arm_R/user_btn')
    assert sorted(recording.episode_topics(('L', 'R'), cameras) + buttons) == sorted(topics)


@pytest.mark.parametrize('value, cameras', [
    (['room_camera', 'right_hand_camera'], ('room_camera', 'right_hand_camera')),
    ('room_camera, left_hand_camera', ('room_camera', 'left_hand_camera')),
    ('', ()), ([], ()), (['a', 'a'], ('a',))])
def test_cameras_parse_from_a_list_or_a_string(value, cameras):
    assert recording.parse_cameras(value) == cameras


@pytest.mark.parametrize('value', [3, None, ['/cameras/room_camera'], ['room camera'], [1], ['']])
def test_bad_cameras_are_refused(value):
    with pytest.raises(ValueError):
        recording.parse_cameras(value)


def test_a_press_acts_once_and_a_held_button_does_not_repeat():
    edge = recording.ButtonEdge()
    readings = [0, 4, 4, 4, 0, 0, 4, 3, 4, 4, 0]
    assert [edge.update(r) for r in readings] == [
        False, True, False, False, False, False, True, False, True, False, False]


def test_the_first_reading_of_a_held_button_is_a_press_and_other_buttons_never_are():
    edge = recording.ButtonEdge()
    assert edge.update(interface.BUTTON_RECORD)
    other = recording.ButtonEdge()
    assert not any(other.update(b) for b in (1, 2, 3, 0, interface.BUTTON_RIGHT))


def test_episode_names_follow_the_start_time_and_never_reuse_a_name():
    start = time.strptime('2024-01-31 14:25:01', '%Y-%m-%d %H:%M:%S')
    assert recording.episode_name(start, lambda n: False) == 'episode_20240131-142501'
    taken = {'episode_20240131-142501', 'episode_20240131-142501_2'}
    assert recording.episode_name(start, taken.__contains__) == 'episode_20240131-142501_3'


@pytest.mark.parametrize('ext', [recording.BAG, recording.ACTIVE, recording.META])
def test_any_file_of_a_name_takes_it(tmp_path, ext):
    (tmp_path / ('episode_x' + ext)).write_text('')
    assert recording.files_taken(str(tmp_path), 'episode_x')
    assert not recording.files_taken(str(tmp_path), 'episode_y')


def test_metadata_holds_every_agreed_key_with_its_type():
    meta = recording.metadata('episode_1', 1706711101.25, 42.5, 3.0, ('R',), ('room_camera',),
                              10.0, {'R': 'ab' * 32, 'L': 'ignored'}, 'pick the cup', True, True,
                              {'/b': 2, '/a': 1}, 'hand the cup over')
    assert list(meta) == ['format_version', 'name', 'start_time', 'start_stamp', 'duration_s',
                          'sides', 'cameras', 'comm_rate_hz', 'ini_fingerprints', 'notes',
                          'task', 'ended_cleanly', 'sim', 'topics']
    assert meta['task'] == 'hand the cup over'
    assert meta['format_version'] == 1
    assert meta['start_time'] == '2024-01-31T14:25:01.250Z'
    assert meta['start_stamp'] == 42.5 and meta['duration_s'] == 3.0
    assert meta['cameras'] == ['room_camera']
    assert meta['sides'] == ['R'] and meta['ini_fingerprints'] == {'R': 'ab' * 32}
    assert meta['topics'] == {'/a': 1, '/b': 2} and meta['notes'] == 'pick the cup'
    assert meta['ended_cleanly'] is True and meta['sim'] is True


def test_metadata_keeps_unknowns_as_null():
    meta = recording.metadata('e', 0.0, 0.0, 0.0, ('L', 'R'), (), None, {}, '', False, False, {})
    assert meta['comm_rate_hz'] is None and meta['ini_fingerprints'] == {'L': None, 'R': None}
    assert meta['task'] == ''  # none
    assert meta['start_time'] == '1970-01-01T00:00:00.000Z'


def test_the_disk_rule_refuses_below_the_threshold_only():
    assert recording.disk_problem(200e6, 200.0) == ''
    problem = recording.disk_problem(199e6, 200.0)
    assert 'disk nearly full' in problem and '199 MB' in problem and '200 MB' in problem
    assert recording.disk_problem(5e9, 6000.0)


def test_an_episode_counts_messages_per_topic_and_reports_its_duration():
    episode = recording.Episode('e', 100.0, 'notes')
    for t in (100.1, 100.2, 101.0):
        episode.count('/a', t)
    episode.count('/b', 101.5)
    status = episode.status('/d/e.bag.active', 112.0, 3_400_000)
    assert status == recording.Status(True, '/d/e.bag.active', 12.0, 3_400_000, 4, '')
    assert episode.topics == {'/a': 3, '/b': 1}


@pytest.mark.parametrize('status, text', [
    (None, 'no recorder'),
    (recording.IDLE, 'not recording'),
    (recording.Status(True, '/d/e.bag', 12.4, 3_400_000, 9, ''), 'REC 00:12, 3.4 MB'),
    (recording.Status(True, '/d/e.bag', 75.0, 0, 9, ''), 'REC 01:15, 0.0 MB'),
    (recording.Status(False, '/d/e.bag', 75.0, 0, 9, ''), 'stopped: e.bag (01:15, 0.0 MB)'),
    (recording.Status(False, '', 0, 0, 0, 'disk nearly full'), 'disk nearly full'),
    # Garbage on /puppet/recording (test_topic_garbage): no exception in the GUI's frame.
    (recording.Status(True, '/d/e.bag', math.inf, 0, 9, ''), 'REC --:--, 0.0 MB'),
    (recording.Status(True, '/d/e.bag', math.nan, 0, 9, ''), 'REC --:--, 0.0 MB'),
    (recording.Status(False, '/d/e.bag', -3e38, 2 ** 64 - 1, 9, ''),
     'stopped: e.bag (--:--, 18446744073709.6 MB)'),
])
def test_the_status_line(status, text):
    assert recording.status_text(status) == text


@pytest.mark.parametrize('text, task', [
    ('pick up the cup and hand it to the patient', 'pick up the cup and hand it to the patient'),
    ('  pick up: the "cup" #2, 50 % ok\n', 'pick up: the "cup" #2, 50 % ok'),  # ends trimmed
    ('heb den Becher über das Bett', 'heb den Becher über das Bett'),
    ('x' * recording.TASK_MAX_CHARS, 'x' * recording.TASK_MAX_CHARS),
    ('', ''), ('   ', ''),  # none
])
def test_a_task_is_one_printable_line_trimmed(text, task):
    assert recording.check_task(text) == task


@pytest.mark.parametrize('text, why', [
    ('pick up\nthe cup', 'one line'), ('pick up\rthe cup', 'one line'),
    ('pick up\u2028the cup', 'one line'),
    ('x' * (recording.TASK_MAX_CHARS + 1), 'at most 500 characters, got 501'),
    ('pick\tup', "printable text: it holds '\\t' at character 5"),
    ('bell\x07', 'printable'), ('nul\x00', 'printable'), ('zero\u200bwidth', 'printable'),
    (None, 'text'), (42, 'text'), (['a'], 'text'),
])
def test_a_task_of_several_lines_too_long_or_unprintable_is_refused(text, why):
    with pytest.raises(ValueError, match='task must be') as error:
        recording.check_task(text)
    assert why in str(error.value)
