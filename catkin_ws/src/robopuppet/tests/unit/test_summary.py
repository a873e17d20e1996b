"""Unit tests of study.summary: the figures of a known study, its table and plots written."""
import math

from robopuppet.study import results, summary

TRIALS = [  # device, practice, success, completion_s, path_m
    ('puppet', True, True, 99.0, 9.0),       # practice: not counted
    ('puppet', False, True, 10.0, 1.0),
    ('puppet', False, True, 20.0, 3.0),
    ('puppet', False, False, '', 5.0),
    ('keyboard', False, False, '', 2.0),
    ('keyboard', False, True, 40.0, 4.0),
]


def write_study(folder):
    for k, (device, practice, success, completion, path) in enumerate(TRIALS, 1):
        row = dict.fromkeys(results.TRIAL_COLUMNS, '')
        row.update(study='s', participant='P%d' % (k % 2), device=device, task='trace',
                   trial=k, practice=practice, success=success, completion_s=completion,
                   path_m=path)
        results.append_row(str(folder / results.TRIALS_CSV), results.TRIAL_COLUMNS, row)
    for device, tlx, sus in (('puppet', 20.0, 80.0), ('puppet', 40.0, 90.0),
                             ('keyboard', 70.0, 50.0)):
        row = dict.fromkeys(results.QUESTIONNAIRE_COLUMNS, 0)
        row.update(participant='P1', device=device, tlx=tlx, sus=sus)
        results.append_row(str(folder / results.QUESTIONNAIRE_CSV),
                           results.QUESTIONNAIRE_COLUMNS, row)


def test_the_figures_per_device(tmp_path):
    write_study(tmp_path)
    table, written = summary.write_summary(str(tmp_path))
    by_device = {row['device']: row for row in table}
    puppet, keyboard = by_device['puppet'], by_device['keyboard']
    assert puppet['trials'] == 3 and keyboard['trials'] == 2
    assert math.isclose(puppet['success_rate'], 2 / 3) and keyboard['success_rate'] == 0.5
    assert puppet['median_completion_s'] == 15.0 and keyboard['median_completion_s'] == 40.0
    assert puppet['median_path_m'] == 3.0 and keyboard['median_path_m'] == 3.0
    assert puppet['tlx_mean'] == 30.0 and puppet['sus_mean'] == 85.0
    assert keyboard['tlx_mean'] == 70.0
    rows = results.read_rows(str(tmp_path / summary.SUMMARY_CSV))
    assert [r['device'] for r in rows] == ['puppet', 'keyboard']
    assert rows[0]['median_completion_s'] == '15.0000'
    markdown = (tmp_path / summary.SUMMARY_MD).read_text()
    assert '| puppet | 3 | 67 % | 15.0 | 3.00 | 30.0 | 85.0 | 2 |' in markdown
    for name in summary.PLOTS.values():
        assert str(tmp_path / name) in written
        assert (tmp_path / name).read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'


def test_a_second_summary_replaces_the_first(tmp_path):
    write_study(tmp_path)
    summary.write_summary(str(tmp_path), plots=False)
    summary.write_summary(str(tmp_path), plots=False)
    assert len(results.read_rows(str(tmp_path / summary.SUMMARY_CSV))) == 2


def test_a_device_without_questionnaires_or_successes_shows_dashes():
    table = summary.summarize([{'device': 'marker', 'practice': 'false', 'success': 'false',
                                'completion_s': '', 'path_m': '0.5', 'participant': 'P1'}], [])
    assert table[0]['trials'] == 1 and table[0]['success_rate'] == 0.0
    assert math.isnan(table[0]['median_completion_s']) and math.isnan(table[0]['tlx_mean'])
    assert '| marker | 1 | 0 % | - | 0.50 | - | - | 1 |' in summary.markdown(table, 't')


def test_the_command_exits_1_without_trials_and_0_with(tmp_path, capsys):
    assert summary.main([str(tmp_path)]) == 1
    write_study(tmp_path)
    assert summary.main([str(tmp_path), '--no-plots']) == 0
    assert '| keyboard | 2 | 50 % |' in capsys.readouterr().out
