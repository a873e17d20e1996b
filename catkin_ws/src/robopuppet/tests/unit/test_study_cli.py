"""Unit tests of study.study_cli: the command's arguments, the settings, the exit codes."""
import pytest

from robopuppet.study import study_cli


def test_arguments_override_parameters_which_override_defaults(monkeypatch):
    monkeypatch.setenv('ROS_HOME', '/lab/ros')
    args = study_cli.parser().parse_args(['--participant', 'P01', '--devices', 'puppet, marker',
                                          '--trials', '3'])
    merged = study_cli.settings({'trials': 2, 'practice': 0, 'tasks': ['trace'],
                                 'events': {'keyboard': '~/kb'}, 'unknown': 1}, args)
    assert merged['devices'] == ['puppet', 'marker'] and merged['tasks'] == ['trace']
    assert merged['trials'] == 3 and merged['practice'] == 0 and 'unknown' not in merged
    assert merged['results_dir'] == '/lab/ros/robopuppet/studies/study'
    assert not merged['events']['keyboard'].startswith('~')


@pytest.mark.parametrize('params', [{'events': ['a']}, {'trial_timeout': -1}, {'trials': 'x'}])
def test_bad_parameters_are_refused(params):
    with pytest.raises(ValueError):
        study_cli.settings(params)


def test_help_names_the_exit_codes(capsys):
    with pytest.raises(SystemExit) as leaving:
        study_cli.parser().parse_args(['--help'])
    assert leaving.value.code == 0
    assert 'exit codes: 0' in capsys.readouterr().out


def test_exit_codes():
    assert study_cli.exit_code('bad participant id', 'idle') == study_cli.EXIT_USAGE
    assert study_cli.exit_code('', 'done') == study_cli.EXIT_DONE
    assert study_cli.exit_code('', 'stopped') == study_cli.EXIT_STOPPED
