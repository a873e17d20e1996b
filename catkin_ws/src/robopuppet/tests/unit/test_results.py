"""Unit tests of study.results: whole rows appended once, read back, participants' order."""
import csv

import pytest

from robopuppet.study import results

COLUMNS = ('participant', 'device', 'value')


def row(participant='P01', device='puppet', value=1.5):
    return {'participant': participant, 'device': device, 'value': value}


def test_the_header_is_written_once_and_rows_are_appended(tmp_path):
    path = str(tmp_path / 'sub' / 'trials.csv')
    results.append_row(path, COLUMNS, row())
    results.append_row(path, COLUMNS, row('P02', value=True))
    lines = open(path).read().splitlines()
    assert lines == ['participant,device,value', 'P01,puppet,1.5000', 'P02,puppet,true']
    assert results.read_rows(path) == [
        {'participant': 'P01', 'device': 'puppet', 'value': '1.5000'},
        {'participant': 'P02', 'device': 'puppet', 'value': 'true'}]


def test_an_append_after_a_crash_mid_row_leaves_whole_lines(tmp_path):
    path = str(tmp_path / 'trials.csv')
    results.append_row(path, COLUMNS, row())
    with open(path, 'a') as handle:
        handle.write('P02,keyb')   # the crash: a row cut off
    results.append_row(path, COLUMNS, row('P03'))
    assert [r['participant'] for r in results.read_rows(path)] == ['P01', 'P03']
    with open(path, newline='') as handle:
        assert all(len(r) == 3 for r in csv.reader(handle))


def test_a_crash_mid_header_gets_a_whole_header(tmp_path):
    path = str(tmp_path / 'trials.csv')
    with open(path, 'w') as handle:
        handle.write('particip')
    results.append_row(path, COLUMNS, row())
    assert open(path).read() == 'participant,device,value\nP01,puppet,1.5000\n'


def test_a_file_with_another_header_is_not_appended_to(tmp_path):
    path = str(tmp_path / 'trials.csv')
    with open(path, 'w') as handle:
        handle.write('a,b\n1,2\n')
    with pytest.raises(results.ResultsError):
        results.append_row(path, COLUMNS, row())
    assert open(path).read() == 'a,b\n1,2\n'


def test_a_row_without_a_column_is_refused(tmp_path):
    with pytest.raises(results.ResultsError):
        results.append_row(str(tmp_path / 'x.csv'), COLUMNS, {'participant': 'P01'})


@pytest.mark.parametrize('participant', ['', 'P 01', 'P01/..', 'a' * 41, 'é', None, 'P01\n'])
def test_bad_participant_ids_are_refused(participant):
    with pytest.raises(results.ResultsError):
        results.check_participant(participant)


@pytest.mark.parametrize('participant', ['P01', 'a' * 40, 'lab-3_x'])
def test_good_participant_ids_pass(participant):
    assert results.check_participant(participant) == participant


def test_a_participants_index_is_the_order_of_first_appearance(tmp_path):
    folder = str(tmp_path)
    assert results.participant_index(folder, 'P05') == 0
    for participant in ('P05', 'P02', 'P05', 'P09'):
        results.append_row(str(tmp_path / results.TRIALS_CSV), COLUMNS, row(participant))
    assert results.participants(folder) == ['P05', 'P02', 'P09']
    assert results.participant_index(folder, 'P02') == 1
    assert results.participant_index(folder, 'P01') == 3
