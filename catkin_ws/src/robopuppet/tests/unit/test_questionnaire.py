"""Tests of the questionnaire's scoring (known answers) and its checks of incomplete answers."""
import pytest

from robopuppet.study import questionnaire
from robopuppet_msgs.msg import Questionnaire

BEST_SUS = [5, 1, 5, 1, 5, 1, 5, 1, 5, 1]   # agrees with every good, disagrees with every bad


def test_the_instruments_have_six_scales_and_ten_statements_in_the_messages_order():
    assert [s.name for s in questionnaire.TLX_SCALES] == [
        'Mental demand', 'Physical demand', 'Temporal demand', 'Performance', 'Effort',
        'Frustration']
    assert questionnaire.TLX_SCALES[3][2:] == ('perfect', 'failure')   # high is worse
    assert len(questionnaire.SUS_ITEMS) == 10
    assert questionnaire.SUS_ITEMS[1] == 'I found the system unnecessarily complex.'
    assert 'robopuppet.study.questionnaire.TLX_SCALES' in Questionnaire._full_text


@pytest.mark.parametrize('ratings, raw', [
    ([0] * 6, 0.0), ([100] * 6, 100.0), ([10, 20, 30, 40, 50, 60], 35.0),
    ([55, 70, 25, 30, 65, 40], 47.5)])
def test_raw_tlx_is_the_mean_of_the_six(ratings, raw):
    assert questionnaire.tlx_raw(ratings) == pytest.approx(raw)


@pytest.mark.parametrize('answers, score', [
    (BEST_SUS, 100.0),
    ([1, 5, 1, 5, 1, 5, 1, 5, 1, 5], 0.0),
    ([3] * 10, 50.0),
    ([5] * 10, 50.0),            # odd items 5 x 4 = 20, even items 5 x 0 = 0: 20 x 2.5
    ([4, 2, 4, 1, 4, 2, 5, 2, 4, 3], 77.5),   # (3+3+3+4+3) + (3+4+3+3+2) = 31
])
def test_sus_scores_odd_items_up_and_even_items_down(answers, score):
    assert questionnaire.sus_score(answers) == score


def test_a_sus_that_swapped_odd_and_even_would_be_caught():
    assert questionnaire.sus_score([5, 3, 3, 3, 3, 3, 3, 3, 3, 3]) == 55.0
    assert questionnaire.sus_score([3, 5, 3, 3, 3, 3, 3, 3, 3, 3]) == 45.0


def test_complete_answers_pass_the_check():
    assert questionnaire.check_answers([50.0] * 6, BEST_SUS) == ''
    assert questionnaire.check_answers([0, 5, 100, 35, 50, 95], bytes(BEST_SUS)) == ''


@pytest.mark.parametrize('tlx, sus, why', [
    ([50] * 6, [3] * 9, 'SUS needs 10 answers, got 9'),
    ([50] * 6, [3, 3, None, 3, 3, 3, 3, 3, 3, 3], 'SUS statement 3 is not answered'),
    ([50] * 6, [3] * 9 + [6], 'SUS statement 10 must be answered 1..5, got 6'),
    ([50] * 6, [0] + [3] * 9, 'SUS statement 1 must be answered 1..5, got 0'),
    ([50] * 6, [2.5] + [3] * 9, 'SUS statement 1 must be answered 1..5, got 2.5'),
    ([50] * 5, [3] * 10, 'NASA-TLX needs 6 ratings, got 5'),
    ([50, None, 50, 50, 50, 50], [3] * 10, 'Physical demand is not rated'),
    ([50, 50, 50, 50, 50, 101], [3] * 10, 'Frustration must be rated 0..100, got 101'),
    ([float('nan')] + [50] * 5, [3] * 10, 'Mental demand must be rated 0..100, got nan'),
])
def test_incomplete_or_bad_answers_say_what_is_wrong(tlx, sus, why):
    assert questionnaire.check_answers(tlx, sus) == why


def test_the_scores_refuse_what_the_check_refuses():
    with pytest.raises(ValueError, match='SUS statement 2 is not answered'):
        questionnaire.sus_score([3, None] + [3] * 8)
    with pytest.raises(ValueError, match='Effort must be rated'):
        questionnaire.tlx_raw([50, 50, 50, 50, -5, 50])
