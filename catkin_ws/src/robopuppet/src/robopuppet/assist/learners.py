"""The assist's learners: train a Predictor of the follower arm from demonstrations, and run it.

Pure (numpy; scikit-learn while training). A Predictor maps the leader arm's recent motion
(features: its pose and smoothed velocity) to the follower's 7 joint angles and its gripper, by
Gaussian mixture regression ('gmr') or locally weighted regression ('lwr'), with a confidence.

Confidence: each method scores how unlike its training data an input is (gmr: -log p(x); lwr:
the distance to the nearest training sample). Training holds demonstrations aside (the
method's calibration_folds: 1, a fifth of them; k, each once in k groups), fits the method to
the rest, and scores the held-aside steps: `score_ref` is their median, `score_high` their
CALIBRATION_QUANTILE quantile, and the threshold lies the method's `margin` times the way from
`score_ref` to `score_high` beyond `score_high`. Confidence is 1 at or below
`score_ref`, falls linearly to CONFIDENCE_THRESHOLD (0.5) at the threshold and to 0 at twice
its distance from `score_ref`; a prediction is familiar at confidence >= 0.5. The model kept
is then fitted to all the training demonstrations.
"""
import collections

import numpy as np

from robopuppet.assist import features, gmr, lwr

METHODS = ('gmr', 'lwr')
CONFIDENCE_THRESHOLD = 0.5
CALIBRATION_QUANTILE = 0.999
ASIDE_FRACTION = 0.2
GRIPPER_CLOSED = 0.5  # the predicted gripper output (0 open, 1 closed) above which it closes

Prediction = collections.namedtuple('Prediction', 'positions gripper_closed confidence familiar')
Prediction.__doc__ = """One step's prediction: positions, the follower's 7 angles (rad, puppet
joint order); gripper_closed (bool); confidence 0..1; familiar (confidence >= the threshold)."""


class LearnerError(ValueError):
    """The demonstrations cannot train a model (too few, unknown method)."""


def arm(demo, side):
    """Return a Demo's (angles (N, 7), gripper closed (N,)) of Baxter's arm side."""
    return getattr(demo, side), getattr(demo, side + '_closed')


def demo_data(demo, leader, follower, settings=None):
    """Return (x (N, 14), y (N, 8)): a Demo's features of the leader and outputs of the
    follower."""
    x = features.sequence_features(demo.t, arm(demo, leader)[0], settings)
    return x, features.outputs(*arm(demo, follower))


class Predictor:
    """A trained model, stepped with the leader's poses as they come.

    Args:
        header: dict: method, leader, follower, task, features (features.SETTINGS),
            settings (the method's), score_ref, score_threshold, and anything more to keep.
        arrays: {name: array}: x_mean, x_scale, y_mean, y_scale and the method's ARRAYS.
    """

    def __init__(self, header, arrays):
        self.header, self.arrays = dict(header), dict(arrays)
        self.method = header['method']
        self.leader, self.follower, self.task = header['leader'], header['follower'], \
            header['task']
        if self.method == 'gmr':
            self._model = gmr.GmrModel(arrays)
        elif self.method == 'lwr':
            self._model = lwr.LwrModel(arrays, header.get('settings'))
        else:
            raise LearnerError('unknown method %r (known: %s)' % (self.method, ', '.join(METHODS)))
        self._scaling = features.Scaling(*(np.asarray(arrays[name], float)
                                           for name in features.Scaling._fields))
        self._ref = float(header['score_ref'])
        self._span = max(float(header['score_threshold']) - self._ref, 1e-9)
        self._filter = features.VelocityFilter(header.get('features'))

    def reset(self):
        """Forget the leader's past motion (its velocity): call when a new motion starts."""
        self._filter.reset()

    def step(self, t, leader_positions):
        """Return the Prediction after the leader's pose (7 angles, rad) measured at t (s)."""
        x = self._filter.step(t, leader_positions)
        y, score = self._model.predict((x - self._scaling.x_mean) / self._scaling.x_scale)
        y = y * self._scaling.y_scale + self._scaling.y_mean
        confidence = self.confidence(score)
        return Prediction([float(v) for v in y[:features.JOINTS]],
                          bool(y[features.JOINTS] >= GRIPPER_CLOSED), confidence,
                          confidence >= CONFIDENCE_THRESHOLD)

    def confidence(self, score):
        """Return the confidence 0..1 of a novelty score (see the module's docstring)."""
        return float(np.clip(1.0 - 0.5 * (score - self._ref) / self._span, 0.0, 1.0))

    def predict_demo(self, demo):
        """Return (positions (N, 7), closed (N,), confidence (N,)) over a Demo's leader motion,
        as step() would give them from a reset."""
        x, _ = demo_data(demo, self.leader, self.follower, self.header.get('features'))
        y, scores = self._model.predict_many((x - self._scaling.x_mean) / self._scaling.x_scale)
        y = y * self._scaling.y_scale + self._scaling.y_mean
        confidence = np.clip(1.0 - 0.5 * (scores - self._ref) / self._span, 0.0, 1.0)
        return y[:, :features.JOINTS], y[:, features.JOINTS] >= GRIPPER_CLOSED, confidence


def _stack(demos, leader, follower, settings):
    pairs = [demo_data(d, leader, follower, settings) for d in demos]
    return np.concatenate([p[0] for p in pairs]), np.concatenate([p[1] for p in pairs])


def _fit_arrays(method, x, y, seed, settings):
    if method == 'gmr':
        return gmr.fit(x, y, seed, settings)
    return lwr.fit(x, y, settings)


def _scores(method, arrays, x, settings):
    """Return the novelty scores of inputs x (scaled) under a method's arrays, and for lwr the
    nearest distances too (the bandwidth's calibration)."""
    if method == 'gmr':
        return gmr.GmrModel(arrays).predict_many(x)[1]
    return lwr.LwrModel(arrays, settings).nearest(x)


def calibration_split(count, folds, seed):
    """Return [(kept indices, aside indices)] of count demonstrations: with folds >= 2, each
    demonstration aside once in min(folds, count) groups; else one split, ASIDE_FRACTION (at
    least 1) aside. Chosen by seed."""
    order = np.random.default_rng(seed).permutation(count)
    if folds >= 2:
        groups = np.array_split(order, min(folds, count))
        return [(np.setdiff1d(order, group), group) for group in groups]
    aside = max(1, int(round(ASIDE_FRACTION * count)))
    return [(order[aside:], order[:aside])]


def train(demos, method, leader, follower, task='', seed=0, settings=None, feature_settings=None):
    """Return a Predictor of method fitted to demos (a list of Demo), calibrated as the module
    says.

    Raises:
        LearnerError: an unknown method, or fewer than 2 demonstrations.
    """
    if method not in METHODS:
        raise LearnerError('unknown method %r (known: %s)' % (method, ', '.join(METHODS)))
    if len(demos) < 2:
        raise LearnerError('training needs at least 2 demonstrations, got %d' % len(demos))
    feature_settings = dict(features.SETTINGS, **(feature_settings or {}))
    settings = dict(gmr.SETTINGS if method == 'gmr' else lwr.SETTINGS, **(settings or {}))
    x, y = _stack(demos, leader, follower, feature_settings)
    scaling = features.fit_scaling(x, y, feature_settings)

    def scaled(xy):
        return ((xy[0] - scaling.x_mean) / scaling.x_scale,
                (xy[1] - scaling.y_mean) / scaling.y_scale)
    scores = []
    for kept, aside in calibration_split(len(demos), int(settings['calibration_folds']), seed):
        x_kept, y_kept = scaled(_stack([demos[i] for i in kept], leader, follower,
                                       feature_settings))
        x_aside, _ = scaled(_stack([demos[i] for i in aside], leader, follower,
                                   feature_settings))
        scores.append(_scores(method, _fit_arrays(method, x_kept, y_kept, seed, settings),
                              x_aside, settings))
    scores = np.concatenate(scores)
    arrays = _fit_arrays(method, *scaled((x, y)), seed, settings)
    if method == 'lwr':
        arrays['bandwidth'] = np.array(max(float(np.median(scores)), 1e-3))
    ref = float(np.median(scores))
    high = float(np.quantile(scores, CALIBRATION_QUANTILE))
    header = {'method': method, 'leader': leader, 'follower': follower, 'task': task,
              'features': feature_settings, 'settings': settings, 'score_ref': ref,
              'score_threshold': high + settings['margin'] * max(high - ref, 1e-6),
              'calibration': {'aside_steps': len(scores),
                              'quantile': CALIBRATION_QUANTILE}}
    arrays.update(scaling._asdict())
    return Predictor(header, arrays)
