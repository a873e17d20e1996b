"""Unit tests of an episode's task in the recorder (session.Recorder): the task given, else the
recorder's ~task, checked at each start and kept through the stop and a repair."""
import os

import pytest
import yaml
from std_msgs.msg import Float32

from robopuppet.episodes import episode_files, recording
from robopuppet.episodes.session import Recorder
from test_session import files, raw


def start(recorder, task, notes='notes'):
    return recorder.start(notes, 100.0, 1706711101.0, 10.0, {'R': 'f' * 64}, True, task)


def meta_of(bag_path):
    return yaml.safe_load(open(bag_path[:-len(recording.BAG)] + recording.META))


@pytest.mark.parametrize('given, default, task', [
    ('pick up the cup', 'hand it over', 'pick up the cup'),   # the request's wins
    ('', 'hand it over', 'hand it over'),                      # empty: the recorder's ~task
    ('  \t ', ' hand it over ', 'hand it over'),               # blank too; both trimmed
    ('', '', ''),                                               # none
])
def test_the_task_given_else_the_recorders_is_in_the_metadata_from_start_to_stop(
        tmp_path, given, default, task):
    recorder = Recorder(str(tmp_path), ('R',), (), 200.0, files(), default)
    ok, error, episode = start(recorder, given)
    assert ok and error == ''
    assert meta_of(episode)['task'] == task            # at the start, before any stop
    assert recorder.stop('other notes', 101.0)[0]
    assert meta_of(episode)['task'] == task and meta_of(episode)['notes'] == 'other notes'


@pytest.mark.parametrize('given, default, why', [
    ('pick up\nthe cup', 'fine', 'task must be one line'),
    ('x' * 501, 'fine', 'task must be at most 500 characters'),
    ('bell\x07', '', 'task must be printable text'),
    ('', 'two\nlines', "the recorder's ~task is not valid"),
    ('', 7, "the recorder's ~task is not valid (give a task with the start, or fix ~task): "
            'task must be text, got 7'),
])
def test_a_bad_task_starts_nothing_and_says_why(tmp_path, given, default, why):
    recorder = Recorder(str(tmp_path / 'episodes'), ('R',), (), 200.0, files(), default)
    ok, error, episode = start(recorder, given)
    assert not ok and why in error and episode == ''
    assert not recorder.recording() and why in recorder.status(100.0).problem
    assert not os.path.exists(str(tmp_path / 'episodes'))  # no folder, no bag, no .yaml


def test_a_bad_default_refuses_only_starts_without_a_task_of_their_own(tmp_path):
    recorder = Recorder(str(tmp_path), ('R',), (), 200.0, files(), 'x' * 600)
    assert not start(recorder, '')[0]
    ok, _, episode = start(recorder, 'pick up the cup')
    assert ok and meta_of(episode)['task'] == 'pick up the cup'


def test_a_repaired_episode_keeps_its_task(tmp_path):
    recorder = Recorder(str(tmp_path), ('R',), (), 200.0, files(), '')
    ok, _, episode = start(recorder, 'pick up the cup')
    recorder.write('/x', raw(Float32(1.0), '/x'), 100.5)
    recorder.tick(100.6)        # flushed; then the process dies: its .bag.active and the
    recorder._writer.abandon()  # start's metadata are left
    repaired = episode_files.repair(episode + '.active')
    meta = meta_of(repaired)
    assert repaired == episode and meta['ended_cleanly'] is False
    assert meta['task'] == 'pick up the cup' and meta['topics'] == {'/x': 1}
