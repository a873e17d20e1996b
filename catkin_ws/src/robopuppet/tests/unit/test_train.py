"""Training by method, held-out evaluation, and the rule that keeps one."""
import numpy as np
import pytest

import assist_synthetic
from robopuppet.assist import learners, train


def test_the_split_holds_out_whole_demonstrations_by_seed():
    training, held = train.split(12, 0.25, seed=3)
    assert len(held) == 3 and sorted(training + held) == list(range(12))
    assert train.split(12, 0.25, seed=3) == (training, held)
    assert train.split(12, 0.25, seed=4) != (training, held)
    assert len(train.split(3, 0.01, 0)[1]) == 1


@pytest.mark.parametrize('count, holdout', [(2, 0.25), (3, 0.5), (10, 0.9)])
def test_too_few_to_train_and_hold_out_is_an_error(count, holdout):
    with pytest.raises(train.TrainError, match='record more'):
        train.split(count, holdout, 0)


class Perfect:
    """A stand-in Predictor that predicts the follower exactly, familiar but at the end."""
    leader, follower = 'right', 'left'

    def predict_demo(self, demo):
        confidence = np.ones(len(demo.t))
        confidence[-1] = 0.2
        return demo.left + 0.01, demo.left_closed, confidence

    def reset(self):
        pass

    def step(self, t, positions):
        return None


def test_evaluate_measures_error_agreement_familiarity_and_the_task_metric():
    demos = [assist_synthetic.demo(seed) for seed in range(2)]
    seen = []

    def metrics(left_q, right_q):
        seen.append((left_q, right_q))
        return {'spread': float(np.abs(left_q - right_q).max())}
    figures = train.evaluate(Perfect(), demos, metrics)
    assert np.isclose(figures['error_p50_rad'], 0.01) and np.isclose(figures['error_p99_rad'],
                                                                      0.01)
    assert figures['gripper_agreement'] == 1.0
    steps = sum(len(d.t) for d in demos)
    assert np.isclose(figures['familiar'], 1 - 2 / steps)
    assert np.allclose(seen[1][0], demos[1].left + 0.01) and np.allclose(seen[1][1], demos[1].right)
    assert figures['task']['spread'] == max(np.abs(d.left + 0.01 - d.right).max() for d in demos)
    assert figures['step_p99_ms'] >= figures['step_p50_ms'] >= 0


def figures(error_p99, familiar, task=None):
    result = {'error_p50_rad': error_p99 / 2, 'error_p99_rad': error_p99, 'familiar': familiar,
              'gripper_agreement': 1.0, 'step_p50_ms': 0.1, 'step_p99_ms': 0.2, 'train_s': 1.0}
    return dict(result, task=task) if task is not None else result


def test_choose_keeps_the_most_accurate_method_that_qualifies():
    results = {'gmr': figures(0.05, 0.98), 'lwr': figures(0.08, 0.995)}
    assert train.choose(results)[0] == 'lwr'
    results = {'gmr': figures(0.05, 1.0, {'tilt_deg': 9.0}),
               'lwr': figures(0.08, 1.0, {'tilt_deg': 4.0})}
    assert train.choose(results, {'tilt_deg': 5.0})[0] == 'lwr'
    assert train.choose(results)[0] == 'gmr'
    method, reason = train.choose({'gmr': figures(0.05, 0.5), 'lwr': figures(0.08, 0.5)})
    assert method == 'gmr' and reason.startswith('no method qualified')


def test_the_table_marks_a_failed_bound():
    lines = train.table({'gmr': figures(0.05, 1.0, {'tilt_deg': 9.0})}, {'tilt_deg': 5.0})
    assert len(lines) == 2 and 'tilt_deg 9 (<= 5 FAILS)' in lines[1]
    assert '(task unknown' in train.table({'lwr': figures(0.05, 1.0)})[1]


def test_train_all_trains_each_method_and_returns_the_chosen_one():
    demos = [assist_synthetic.demo(seed) for seed in range(8)]
    lines = []
    predictor, results, _, (training, held) = train.train_all(
        demos, learners.METHODS, 'right', 'left', 'synthetic', 0.25, 0, say=lines.append)
    assert set(results) == set(learners.METHODS) and len(held) == 2 and len(training) == 6
    assert predictor.method == train.choose(results)[0] and predictor.task == 'synthetic'
    assert all(results[m]['error_p99_rad'] < 0.15 for m in results)
    assert any('gmr: trained in' in line for line in lines)


def test_evaluate_without_timing_gives_nan_times():
    figures = train.evaluate(Perfect(), [assist_synthetic.demo(0)], timing_demos=0)
    assert np.isnan(figures['step_p99_ms']) and figures['error_p99_rad'] > 0
