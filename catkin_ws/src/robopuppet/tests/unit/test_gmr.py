"""Gaussian mixture regression: closed-form conditioning and the novelty score."""
import numpy as np

from robopuppet.assist import gmr


def test_one_gaussian_conditions_to_its_regression_line():
    mean = np.array([[1.0, 2.0]])
    cov = np.array([[[4.0, 1.0], [1.0, 1.0]]])
    model = gmr.GmrModel(gmr.conditioning(np.array([1.0]), mean, cov, 1))
    y, score = model.predict(np.array([3.0]))
    assert np.allclose(y, [2.0 + 0.25 * (3.0 - 1.0)])
    # -log N(3; 1, 4)
    assert np.isclose(score, 0.5 * np.log(2 * np.pi * 4.0) + 0.5 * (2.0 ** 2) / 4.0)


def test_the_input_picks_its_component():
    means = np.array([[-3.0, 10.0], [3.0, -10.0]])
    covs = np.tile(np.eye(2) * 0.1, (2, 1, 1))
    model = gmr.GmrModel(gmr.conditioning(np.array([0.5, 0.5]), means, covs, 1))
    assert np.isclose(model.predict(np.array([-3.0]))[0][0], 10.0)
    assert np.isclose(model.predict(np.array([3.0]))[0][0], -10.0)


def test_a_fit_follows_a_curve_and_scores_strangers_higher():
    x = np.linspace(-2, 2, 2000)[:, None]
    y = np.column_stack([np.sin(x[:, 0]), x[:, 0] ** 2])
    model = gmr.GmrModel(gmr.fit(x, y, seed=0, settings={'components': 8}))
    predicted, scores = model.predict_many(x)
    assert np.abs(predicted - y).max() < 0.1
    assert model.predict(np.array([6.0]))[1] > scores.max() + 5
    one, score = model.predict(x[123])
    assert np.allclose(one, predicted[123]) and np.isclose(score, scores[123])
