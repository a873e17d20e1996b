"""Gaussian mixture regression (Ghahramani and Jordan 1994; Calinon, Guenter and Billard 2007):
a Gaussian mixture fitted on the joint [input, output] space, conditioned on the input in
closed form.

Pure (numpy; scikit-learn only to fit). Inputs and outputs are scaled to unit spread
(features.Scaling) before they come here. fit() runs expectation-maximisation
(sklearn.mixture.GaussianMixture, full covariances); GmrModel keeps per component what the
conditioning needs, so a prediction is a few small matrix products: the inverse Cholesky factor
of the input block, its log normaliser, and the regression y = a x + b of the output on the input.
Its novelty score is -log p(x), the input's negative log marginal likelihood under the mixture.
"""
import numpy as np

SETTINGS = {
    'margin': 1.0,  # threshold beyond the held-aside scores (one fold: wider)
    'calibration_folds': 1,  # one held-aside fit to set the confidence (EM's time)
    'components': 12,       # Gaussians in the mixture
    'reg_covar': 1e-3,      # added to each covariance's diagonal (unit-spread data)
    'max_samples': 20000,   # training rows beyond this are thinned evenly (EM's time)
    'max_iter': 200,
}
ARRAYS = ('log_weights', 'mean_x', 'chol_inv', 'log_norm', 'reg_a', 'reg_b')


def fit(x, y, seed=0, settings=None):
    """Return GmrModel's arrays {name: array} fitted to inputs x (N, d) and outputs y (N, o)."""
    from sklearn.mixture import GaussianMixture  # only training needs it (slow to import)
    settings = dict(SETTINGS, **(settings or {}))
    data = np.column_stack([x, y])
    stride = max(1, int(np.ceil(len(data) / settings['max_samples'])))
    data = data[::stride]
    mixture = GaussianMixture(n_components=min(settings['components'], len(data)),
                              covariance_type='full', reg_covar=settings['reg_covar'],
                              max_iter=settings['max_iter'], random_state=seed)
    mixture.fit(data)
    return conditioning(mixture.weights_, mixture.means_, mixture.covariances_, x.shape[1])


def conditioning(weights, means, covariances, d):
    """Return GmrModel's arrays of a mixture (weights (K,), means (K, d+o), covariances
    (K, d+o, d+o)) conditioned on its first d dimensions."""
    s_xx = covariances[:, :d, :d]
    s_yx = covariances[:, d:, :d]
    chol = np.linalg.cholesky(s_xx)
    chol_inv = np.linalg.inv(chol)
    log_det = 2.0 * np.log(np.diagonal(chol, axis1=1, axis2=2)).sum(axis=1)
    reg_a = s_yx @ np.linalg.inv(s_xx)
    reg_b = means[:, d:] - np.einsum('kod,kd->ko', reg_a, means[:, :d])
    return {'log_weights': np.log(weights), 'mean_x': means[:, :d], 'chol_inv': chol_inv,
            'log_norm': -0.5 * (log_det + d * np.log(2.0 * np.pi)),
            'reg_a': reg_a, 'reg_b': reg_b}


class GmrModel:
    """Predict outputs from an input with the conditioned mixture.

    Args:
        arrays: {name: array} of ARRAYS, as fit() returns them.
    """

    def __init__(self, arrays):
        self._log_w = np.asarray(arrays['log_weights'], float)
        self._mean_x = np.asarray(arrays['mean_x'], float)
        self._chol_inv = np.asarray(arrays['chol_inv'], float)
        self._log_norm = np.asarray(arrays['log_norm'], float)
        self._reg_a = np.asarray(arrays['reg_a'], float)
        self._reg_b = np.asarray(arrays['reg_b'], float)
        k, o, d = self._reg_a.shape
        self._a_flat = self._reg_a.reshape(k, o * d)
        self._shape = (o, d)

    def predict(self, x):
        """Return (y (o,), score): the conditional mean of the outputs at input x (d,), and
        -log p(x) (higher: less like the training data)."""
        z = np.einsum('kij,kj->ki', self._chol_inv, x - self._mean_x)
        log_p = self._log_w + self._log_norm - 0.5 * np.einsum('ki,ki->k', z, z)
        top = log_p.max()
        h = np.exp(log_p - top)
        total = h.sum()
        h /= total
        y = h @ self._reg_b + (h @ self._a_flat).reshape(self._shape) @ x
        return y, -(top + np.log(total))

    def predict_many(self, x):
        """Return (y (N, o), scores (N,)) for inputs x (N, d), as predict() row by row."""
        z = np.einsum('kij,nkj->nki', self._chol_inv, x[:, None, :] - self._mean_x)
        log_p = self._log_w + self._log_norm - 0.5 * np.einsum('nki,nki->nk', z, z)
        top = log_p.max(axis=1, keepdims=True)
        h = np.exp(log_p - top)
        total = h.sum(axis=1, keepdims=True)
        h /= total
        y = h @ self._reg_b + np.einsum('nk,kod,nd->no', h, self._reg_a, x)
        return y, -(top[:, 0] + np.log(total[:, 0]))
