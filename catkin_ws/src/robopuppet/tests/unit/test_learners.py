"""The assist's learners on synthetic demonstrations (tests/unit/assist_synthetic.py): accurate
on held-out ones, familiar there, unfamiliar soon after the leader departs from them."""
import numpy as np
import pytest

import assist_synthetic
from robopuppet.assist import learners

TRAINING = [assist_synthetic.demo(seed) for seed in range(10)]
HELD_OUT = [assist_synthetic.demo(seed) for seed in range(100, 104)]


@pytest.fixture(scope='module', params=learners.METHODS)
def predictor(request):
    return learners.train(TRAINING, request.param, 'right', 'left', 'synthetic', seed=0)


def test_held_out_demonstrations_are_predicted_and_familiar(predictor):
    errors, familiar, agree = [], [], []
    for demo in HELD_OUT:
        positions, closed, confidence = predictor.predict_demo(demo)
        errors.append(np.abs(positions - demo.left).max(axis=1))
        familiar.append(confidence >= learners.CONFIDENCE_THRESHOLD)
        agree.append(closed == demo.left_closed)
    assert np.percentile(np.concatenate(errors), 99) < 0.1
    assert np.concatenate(familiar).mean() >= 0.99
    assert np.concatenate(agree).mean() >= 0.9


def test_a_departing_leader_is_unfamiliar_within_half_a_second(predictor):
    for seed in (200, 201, 202):
        demo, departed_s = assist_synthetic.unfamiliar(seed)
        _, _, confidence = predictor.predict_demo(demo)
        unfamiliar = confidence < learners.CONFIDENCE_THRESHOLD
        assert not unfamiliar[demo.t < departed_s].any()
        first = demo.t[np.flatnonzero(unfamiliar & (demo.t >= departed_s))[0]]
        assert first - departed_s <= 0.5
        assert unfamiliar[demo.t >= departed_s + 0.5].all()


def test_stepping_gives_the_batch_predictions(predictor):
    demo = HELD_OUT[0]
    positions, closed, confidence = predictor.predict_demo(demo)
    predictor.reset()
    for k in range(0, len(demo.t)):
        prediction = predictor.step(demo.t[k], demo.right[k])
        if k % 25 == 0:
            assert np.allclose(prediction.positions, positions[k])
            assert prediction.gripper_closed == closed[k]
            assert np.isclose(prediction.confidence, confidence[k])
            assert prediction.familiar == (confidence[k] >= 0.5)
    assert len(prediction.positions) == 7 and isinstance(prediction.positions[0], float)


def test_reset_forgets_the_leaders_velocity(predictor):
    demo = HELD_OUT[1]
    for k in range(50):
        predictor.step(demo.t[k], demo.right[k])
    predictor.reset()
    fresh = predictor.step(100.0, demo.right[0])
    predictor.reset()
    assert fresh == predictor.step(0.0, demo.right[0])


def test_the_confidence_scale_is_anchored_on_the_calibration():
    predictor = learners.Predictor(
        {'method': 'lwr', 'leader': 'right', 'follower': 'left', 'task': '', 'score_ref': 1.0,
         'score_threshold': 3.0},
        dict(learners.lwr.fit(np.zeros((3, 14)), np.zeros((3, 8))), x_mean=np.zeros(14),
             x_scale=np.ones(14), y_mean=np.zeros(8), y_scale=np.ones(8)))
    assert [predictor.confidence(s) for s in (0.0, 1.0, 2.0, 3.0, 5.0, 9.0)] == \
        [1.0, 1.0, 0.75, 0.5, 0.0, 0.0]


def test_training_refuses_too_few_demonstrations_and_unknown_methods():
    with pytest.raises(learners.LearnerError, match='at least 2'):
        learners.train(TRAINING[:1], 'gmr', 'right', 'left')
    with pytest.raises(learners.LearnerError, match='unknown method'):
        learners.train(TRAINING, 'svm', 'right', 'left')
