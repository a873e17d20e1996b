"""Locally weighted regression (Atkeson, Moore and Schaal 1997): at each query, a linear model
fitted to the nearest training samples, weighted by a Gaussian kernel of their distance.

Pure (numpy, scipy). Inputs and outputs are scaled to unit spread (features.Scaling) before they
come here. The training samples sit in a k-d tree (scipy.spatial.cKDTree); a prediction takes
the `neighbours` nearest, weights them exp(-d^2 / 2 h^2) (d: a sample's distance beyond the
nearest one's, so that a query far from all still gets a fit; h: `bandwidth`, set from
held-aside demonstrations' distances by learners) and solves a ridge-regularised weighted
least-squares fit of an affine model centred on the query, whose intercept is the prediction.
Its novelty score is the distance to the nearest training sample.
"""
import numpy as np
from scipy.spatial import cKDTree

SETTINGS = {
    'margin': 0.5,  # threshold beyond the held-aside scores (see learners)
    'calibration_folds': 5,  # each demonstration held aside once (fits are cheap)
    'neighbours': 48,   # training samples each prediction fits
    'ridge': 0.001,     # slope penalty, relative to the weights' sum (samples on few paths)
    'thin': 4,          # keep every 4th training step: neighbours then span more demonstrations
    'max_samples': 60000,  # training rows beyond this are thinned further (memory, tree size)
}
ARRAYS = ('train_x', 'train_y', 'bandwidth')


def fit(x, y, settings=None):
    """Return LwrModel's arrays {name: array} of inputs x (N, d) and outputs y (N, o); the
    bandwidth is set to 1 until calibrated."""
    settings = dict(SETTINGS, **(settings or {}))
    stride = max(int(settings['thin']), int(np.ceil(len(x) / settings['max_samples'])))
    return {'train_x': np.array(x[::stride], float), 'train_y': np.array(y[::stride], float),
            'bandwidth': np.array(1.0)}


class LwrModel:
    """Predict outputs from an input by a locally weighted affine fit.

    Args:
        arrays: {name: array} of ARRAYS, as fit() returns them.
        settings: SETTINGS' keys (neighbours, ridge).
    """

    def __init__(self, arrays, settings=None):
        settings = dict(SETTINGS, **(settings or {}))
        self._x = np.asarray(arrays['train_x'], float)
        self._y = np.asarray(arrays['train_y'], float)
        self._tree = cKDTree(self._x)
        self._k = int(min(settings['neighbours'], len(self._x)))
        self._ridge = float(settings['ridge'])
        self.bandwidth = float(arrays['bandwidth'])
        d = self._x.shape[1]
        self._penalty = np.diag(np.r_[0.0, np.ones(d)])  # on the slopes, not the intercept

    def nearest(self, x):
        """Return the distances (N,) of inputs x (N, d) to their nearest training sample."""
        return self._tree.query(x, k=1)[0]

    def predict(self, x):
        """Return (y (o,), score): the local fit's value at input x (d,), and the distance to
        the nearest training sample (higher: less like the training data)."""
        dist, index = self._tree.query(x, k=self._k)
        dist, index = np.atleast_1d(dist), np.atleast_1d(index)
        w = np.exp(-0.5 * ((dist - dist[0]) / self.bandwidth) ** 2)
        design = np.column_stack([np.ones(len(index)), self._x[index] - x])
        weighted = design.T * w
        gram = weighted @ design + self._ridge * w.sum() * self._penalty
        beta = np.linalg.solve(gram, weighted @ self._y[index])
        return beta[0], dist[0]

    def predict_many(self, x):
        """Return (y (N, o), scores (N,)) for inputs x (N, d), as predict() row by row."""
        pairs = [self.predict(row) for row in x]
        return (np.array([p[0] for p in pairs]).reshape(len(x), self._y.shape[1]),
                np.array([p[1] for p in pairs]))
