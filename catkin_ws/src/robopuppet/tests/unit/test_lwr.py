"""Locally weighted regression: a kernel-weighted affine fit around each query."""
import numpy as np

from robopuppet.assist import lwr


def test_a_plane_is_fitted_exactly_between_samples():
    rng = np.random.default_rng(1)
    x = rng.uniform(-1, 1, (500, 3))
    y = x @ np.array([[1.0, -2.0], [0.5, 0.0], [0.0, 3.0]]) + [0.1, -0.2]
    model = lwr.LwrModel(dict(lwr.fit(x, y, {'thin': 1}), bandwidth=np.array(0.3)),
                         {'ridge': 1e-9})
    query = np.array([0.123, -0.4, 0.77])
    value, score = model.predict(query)
    assert np.allclose(value, query @ np.array([[1.0, -2.0], [0.5, 0.0], [0.0, 3.0]])
                       + [0.1, -0.2], atol=1e-6)
    assert np.isclose(score, np.linalg.norm(x - query, axis=1).min())


def test_a_curve_is_followed_and_a_far_query_still_gets_a_finite_answer():
    x = np.linspace(-3, 3, 3000)[:, None]
    y = np.sin(x)
    model = lwr.LwrModel(dict(lwr.fit(x, y, {'thin': 1}), bandwidth=np.array(0.01)))
    predicted, scores = model.predict_many(x[::37])
    assert np.abs(predicted - y[::37]).max() < 0.01
    far, score = model.predict(np.array([50.0]))
    assert np.all(np.isfinite(far)) and np.isclose(score, 47.0)
