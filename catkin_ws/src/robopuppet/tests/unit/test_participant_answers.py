"""Tests of the simulated participant's questionnaire answers."""
import numpy as np

from robopuppet.study import participant_answers


def test_answers_are_plausible_seeded_and_rank_the_devices():
    tlx, sus = participant_answers.answers('keyboard', 7)
    assert len(tlx) == 6 and all(0 <= v <= 100 and v % 5 == 0 for v in tlx)
    assert len(sus) == 10 and all(1 <= v <= 5 for v in sus)
    assert participant_answers.answers('keyboard', 7) == (tlx, sus)
    mean = {d: np.mean([np.mean(participant_answers.answers(d, s)[0]) for s in range(30)])
            for d in ('puppet', 'keyboard')}
    assert mean['puppet'] < mean['keyboard']
