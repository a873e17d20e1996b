"""The forwarder's pure scheduler (tools/netbed/impairment.py): delay, jitter, order, loss, cuts.
No namespaces needed: these run anywhere."""
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..',
                                '..', '..', 'tools'))
from netbed.impairment import Impairment  # noqa: E402


def run(link, count, spacing_s=0.001):
    """Offer `count` packets spaced spacing_s; return {index: release time} of those released."""
    released = {}
    for i in range(count):
        link.offer(i, i * spacing_s)
    t = 0.0
    while link.in_flight():
        t = link.next_release_s()
        for packet in link.due(t):
            released[packet] = t
    return released


def test_delay_without_jitter_is_exact():
    link = Impairment(seed=1)
    link.configure(delay_s=0.05)
    released = run(link, 100)
    assert all(abs(t - i * 0.001 - 0.05) < 1e-9 for i, t in released.items())
    assert link.due(10.0) == [] and link.next_release_s() is None


def test_jitter_spreads_delays_but_never_reorders_nor_releases_early():
    link = Impairment(seed=1)
    link.configure(delay_s=0.05, jitter_s=0.02)
    released = run(link, 1000, spacing_s=0.01)  # sparse: jitter shows, ordering rarely binds
    order = sorted(released, key=lambda i: (released[i], i))
    assert order == sorted(released)
    delays = [released[i] - i * 0.01 for i in released]
    assert min(delays) >= 0.03 - 1e-9
    assert max(delays) - min(delays) > 0.03
    assert 0.045 < sorted(delays)[len(delays) // 2] < 0.06


def test_due_returns_only_what_is_due():
    link = Impairment(seed=1)
    link.configure(delay_s=0.1)
    link.offer('a', 0.0)
    link.offer('b', 0.05)
    assert link.due(0.099) == []
    assert link.due(0.1) == ['a']
    assert link.next_release_s() == pytest.approx(0.15)
    assert link.due(1.0) == ['b']


def test_loss_fraction_and_seed_reproducibility():
    def lost(seed):
        link = Impairment(seed=seed)
        link.configure(loss=0.1)
        return set(range(5000)) - set(run(link, 5000)), link.counts['lost']
    first, counted = lost('7:to-robot')
    assert counted == len(first)
    assert 400 < len(first) < 600
    assert lost('7:to-robot')[0] == first
    assert lost('8:to-robot')[0] != first


def test_the_same_seed_loses_the_same_packets_whatever_the_delay():
    def lost(delay_s, jitter_s):
        link = Impairment(seed=3)
        link.configure(delay_s=delay_s, jitter_s=jitter_s, loss=0.2)
        return set(range(500)) - set(run(link, 500))
    assert lost(0.0, 0.0) == lost(0.05, 0.01)


def test_cut_drops_in_flight_and_new_packets_until_restore():
    link = Impairment(seed=1)
    link.configure(delay_s=0.1)
    link.offer('in flight', 0.0)
    link.cut()
    assert link.in_flight() == 0
    assert link.offer('during', 0.01) is False
    link.restore()
    assert link.offer('after', 0.02) is True
    assert link.due(1.0) == ['after']
    assert link.counts['cut'] == 2


def test_a_full_queue_drops_the_overflow():
    link = Impairment(seed=1, max_queue=3)
    link.configure(delay_s=1.0)
    assert [link.offer(i, 0.0) for i in range(5)] == [True, True, True, False, False]
    assert link.counts['overflow'] == 2


@pytest.mark.parametrize('settings', [{'delay_s': -0.001}, {'jitter_s': -1}, {'loss': 1.5},
                                      {'loss': -0.1}, {'delay_s': float('nan')}])
def test_bad_settings_are_refused_and_change_nothing(settings):
    link = Impairment(seed=1)
    link.configure(delay_s=0.01, jitter_s=0.002, loss=0.1)
    with pytest.raises(ValueError):
        link.configure(**settings)
    assert (link.delay_s, link.jitter_s, link.loss) == (0.01, 0.002, 0.1)
