"""Unit tests of study.plan: the Williams design, the trial list and its seeds."""
import collections
import itertools

import pytest

from robopuppet.study import plan


@pytest.mark.parametrize('n', range(1, 8))
def test_each_row_is_a_permutation_and_each_column_too(n):
    rows = plan.williams_rows(n)
    assert len(rows) == (n if n % 2 == 0 else 2 * n)
    assert all(sorted(row) == list(range(n)) for row in rows)
    for column in zip(*rows):
        assert collections.Counter(column) == {c: len(rows) // n for c in range(n)}


@pytest.mark.parametrize('n', [2, 3, 4, 5, 6])
def test_each_condition_follows_each_other_equally_often(n):
    rows = plan.williams_rows(n)
    pairs = collections.Counter(p for row in rows for p in zip(row, row[1:]))
    assert set(pairs) == set(itertools.permutations(range(n), 2))
    assert len(set(pairs.values())) == 1


@pytest.mark.parametrize('devices', [
    ('puppet', 'keyboard', 'gamepad', 'spacemouse'),
    ('puppet', 'keyboard', 'gamepad', 'spacemouse', 'marker')])
def test_each_device_comes_first_equally_often_over_a_full_set_of_participants(devices):
    count = len(plan.williams_rows(len(devices)))
    firsts = collections.Counter(
        plan.blocks(plan.make_plan('P%d' % k, k, devices, ['reach_hold']))[0]
        for k in range(3 * count))
    assert firsts == {d: 3 * count // len(devices) for d in devices}


def test_an_even_number_of_participants_balances_carry_over_of_four_devices():
    devices = ('puppet', 'keyboard', 'gamepad', 'spacemouse')
    pairs = collections.Counter()
    for k in range(8):
        order = plan.blocks(plan.make_plan('P%d' % k, k, devices, ['trace']))
        pairs.update(zip(order, order[1:]))
    assert len(pairs) == 12 and set(pairs.values()) == {2}


def test_each_block_starts_with_its_practice_trials():
    trials = plan.make_plan('P01', 1, ['puppet', 'marker'], ['trace', 'reach_hold'],
                            practice=1, trials=2)
    assert [t.number for t in trials] == list(range(1, 13))
    for device in ('puppet', 'marker'):
        block = [t.practice for t in trials if t.device == device]
        assert block == [True, True, False, False, False, False]
    # a block is contiguous
    assert [t.device for t in trials] == sorted([t.device for t in trials],
                                                 key=plan.blocks(trials).index)


def test_seeds_are_distinct_and_reproducible_and_follow_the_study_seed():
    args = ('P07', 3, ['puppet', 'keyboard', 'gamepad'], ['reach_hold', 'trace', 'bimanual'])
    first = plan.make_plan(*args, practice=2, trials=3, seed=5)
    assert first == plan.make_plan(*args, practice=2, trials=3, seed=5)
    seeds = [t.seed for t in first]
    assert len(set(seeds)) == len(seeds)
    assert all(0 <= s < 2 ** 32 for s in seeds)
    other = plan.make_plan(*args, practice=2, trials=3, seed=6)
    assert not set(seeds) & {t.seed for t in other}
    # another participant draws other targets for the same device and task
    assert plan.trial_seed(5, 'P07', 'puppet', 'trace', 1, False) != plan.trial_seed(
        5, 'P08', 'puppet', 'trace', 1, False)


@pytest.mark.parametrize('devices, tasks, practice, trials', [
    ([], ['trace'], 1, 1), (['puppet', 'puppet'], ['trace'], 1, 1),
    (['puppet'], [], 1, 1), (['puppet'], ['trace'], -1, 1), (['puppet'], ['trace'], 0, 0)])
def test_a_study_that_cannot_be_planned_is_refused(devices, tasks, practice, trials):
    with pytest.raises(plan.PlanError):
        plan.make_plan('P01', 0, devices, tasks, practice, trials)
