"""Unit tests of an episode's files by name and its metadata file (episodes.metadata)."""
import pytest
import yaml

from robopuppet.episodes import metadata, recording


def test_an_episode_is_found_by_name_bag_or_yaml(tmp_path):
    base = str(tmp_path / 'episode_20240101-120000')
    (tmp_path / ('episode_20240101-120000' + recording.BAG)).write_bytes(b'')
    for given in (base, base + recording.BAG, base + recording.META, base + recording.ACTIVE):
        assert metadata.episode_paths(given) == (base + recording.BAG, base + recording.META)


def test_a_missing_or_still_recorded_bag_is_refused(tmp_path):
    base = str(tmp_path / 'episode_x')
    with pytest.raises(metadata.EpisodeError, match='no such bag'):
        metadata.episode_paths(base)
    (tmp_path / ('episode_x' + recording.ACTIVE)).write_bytes(b'')
    with pytest.raises(metadata.EpisodeError, match='still being recorded'):
        metadata.episode_paths(base)


def test_metadata_round_trips_and_a_missing_file_is_empty(tmp_path):
    path = str(tmp_path / 'e.yaml')
    assert metadata.read_metadata(path) == {} == metadata.metadata_or_empty(path)
    metadata.write_metadata(path, {'name': 'e', 'sides': ['R'], 'duration_s': 1.5})
    assert metadata.read_metadata(path) == {'name': 'e', 'sides': ['R'], 'duration_s': 1.5}
    assert metadata.metadata_or_empty(path) == metadata.read_metadata(path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ['e.yaml']  # no temp file left


@pytest.mark.parametrize('task', ['pick up the cup', 'yes', 'null', '- a: b # c', "it's \"it\"",
                                  '42', 'über 50 %', ''])
def test_a_task_round_trips_as_the_same_string(tmp_path, task):
    path = str(tmp_path / 'e.yaml')
    metadata.write_metadata(path, recording.metadata('e', 0.0, 0.0, 0.0, ('R',), (), None, {},
                                                     '', True, False, {}, task))
    assert metadata.read_metadata(path)['task'] == task  # a string, never YAML's bool or number


@pytest.mark.parametrize('text, error', [('', metadata.EpisodeError),
                                         ('- a list\n', metadata.EpisodeError),
                                         ('{not: yaml: at all\n', yaml.YAMLError)])
def test_a_file_without_a_metadata_dict(tmp_path, text, error):
    path = tmp_path / 'e.yaml'
    path.write_text(text)
    assert metadata.metadata_or_empty(str(path)) == {}
    with pytest.raises(error):
        metadata.read_metadata(str(path))
