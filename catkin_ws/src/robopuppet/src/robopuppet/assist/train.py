"""Train the assist's learners on demonstrations, evaluate them on held-out ones, keep the better.

Pure (numpy): demonstrations come in as assist Demos; the caller reads the episodes and writes
the model (train_cli). The split is by demonstration, so no held-out step was seen in training.
Each method is trained on the training demonstrations and evaluated on the held-out ones
(evaluate's figures); the kept one is chosen by choose()'s rule and is the model as trained on
the training demonstrations alone, so its saved figures are the figures it earned.
"""
import time

import numpy as np

from robopuppet.assist import learners

FAMILIAR_NEEDED = 0.99   # held-out steps a kept method must find familiar


class TrainError(ValueError):
    """The demonstrations cannot be split and trained on as asked."""


def split(count, holdout, seed):
    """Return (training indices, held-out indices) of count demonstrations: round(holdout *
    count) held out (at least 1), chosen by seed, each list sorted.

    Raises:
        TrainError: fewer than 3 demonstrations, or a holdout leaving fewer than 2 to train on.
    """
    if not 0.0 < holdout < 1.0:
        raise TrainError('--holdout must be between 0 and 1, got %g' % holdout)
    held_count = max(1, int(round(holdout * count)))
    if count - held_count < 2:
        raise TrainError('%d demonstration(s) with --holdout %g leave %d to train on: training '
                         'needs 2 and evaluation 1 held out (record more)'
                         % (count, holdout, count - held_count))
    order = np.random.default_rng(seed).permutation(count)
    return sorted(order[held_count:].tolist()), sorted(order[:held_count].tolist())


def evaluate(predictor, demos, metrics=None, timing_demos=1):
    """Return a predictor's figures on held-out demos: error_p50_rad, error_p99_rad (over steps
    of the max over the 7 follower joints of |predicted - demonstrated|), gripper_agreement and
    familiar (fractions of steps), step_p50_ms, step_p99_ms (step()'s wall time over the first
    timing_demos demos, NaN for none; step_cpu_p99_ms: its thread CPU time, without waits for
    a core), and
    with metrics (a function (left_q, right_q) -> {name: value}) the task metric `task`:
    {name: the worst over the demos of it on the demonstrated leader and the predicted
    follower}."""
    errors, agree, familiar, task = [], [], [], {}
    for demo in demos:
        positions, closed, confidence = predictor.predict_demo(demo)
        shown, shown_closed = learners.arm(demo, predictor.follower)
        errors.append(np.abs(positions - shown).max(axis=1))
        agree.append(closed == shown_closed)
        familiar.append(confidence >= learners.CONFIDENCE_THRESHOLD)
        if metrics is not None:
            arms = {predictor.follower: positions,
                    predictor.leader: learners.arm(demo, predictor.leader)[0]}
            for name, value in metrics(arms['left'], arms['right']).items():
                task[name] = max(task.get(name, -np.inf), float(value))
    step_s, cpu_s = [], []
    for demo in demos[:timing_demos]:
        predictor.reset()
        leader = learners.arm(demo, predictor.leader)[0]
        for t, q in zip(demo.t, leader):
            start, cpu = time.perf_counter(), time.thread_time()
            predictor.step(t, q)
            cpu_s.append(time.thread_time() - cpu)
            step_s.append(time.perf_counter() - start)
    errors = np.concatenate(errors)
    step_s, cpu_s = (values or [np.nan] for values in (step_s, cpu_s))  # none timed: NaN
    figures = {'error_p50_rad': float(np.percentile(errors, 50)),
               'error_p99_rad': float(np.percentile(errors, 99)),
               'gripper_agreement': float(np.concatenate(agree).mean()),
               'familiar': float(np.concatenate(familiar).mean()),
               'step_p50_ms': float(np.percentile(step_s, 50) * 1e3),
               'step_p99_ms': float(np.percentile(step_s, 99) * 1e3),
               'step_cpu_p99_ms': float(np.percentile(cpu_s, 99) * 1e3)}
    if metrics is not None:
        figures['task'] = task
    return figures


def within(figures, bounds):
    """Return whether figures' task metric holds every bound ({name: limit}); True without."""
    task = figures.get('task')
    return not bounds or task is None or all(task.get(n, np.inf) <= b for n, b in bounds.items())


def choose(results, bounds=None):
    """Return (method, reason): of results {method: figures}, the lowest error_p99_rad among
    the methods familiar at >= FAMILIAR_NEEDED of held-out steps whose task metric holds
    bounds; if none qualifies, the lowest error_p99_rad of all."""
    qualified = [m for m, f in results.items()
                 if f['familiar'] >= FAMILIAR_NEEDED and within(f, bounds)]
    pool = qualified or list(results)
    method = min(pool, key=lambda m: (results[m]['error_p99_rad'], results[m]['error_p50_rad']))
    rule = ('lowest held-out error p99 among the methods familiar at >= %.0f %% of held-out '
            'steps%s' % (100 * FAMILIAR_NEEDED, ' and within the task bounds' if bounds else ''))
    if not qualified:
        rule = 'no method qualified (%s): lowest held-out error p99' % rule
    return method, rule


def train_all(demos, methods, leader, follower, task='', holdout=0.25, seed=0, metrics=None,
              bounds=None, say=print):
    """Split demos, train and evaluate each method, choose one.

    Returns:
        (predictor, results, reason, (training indices, held-out indices)): the chosen method's
        Predictor, {method: figures (evaluate's, with train_s)}.
    """
    training, held = split(len(demos), holdout, seed)
    train_demos = [demos[i] for i in training]
    held_demos = [demos[i] for i in held]
    steps = sum(len(d.t) for d in train_demos)
    predictors, results = {}, {}
    for method in methods:
        say('%s: training on %d demonstrations (%d steps)...' % (method, len(train_demos), steps))
        start = time.perf_counter()
        predictors[method] = learners.train(train_demos, method, leader, follower, task, seed)
        train_s = time.perf_counter() - start
        say('%s: trained in %.1f s; evaluating on %d held-out demonstrations...'
            % (method, train_s, len(held_demos)))
        results[method] = dict(evaluate(predictors[method], held_demos, metrics), train_s=train_s)
    method, reason = choose(results, bounds)
    return predictors[method], results, reason, (training, held)


def table(results, bounds=None):
    """Return the lines of a table of results {method: figures}, a row per method."""
    lines = ['%-6s %8s %12s %12s %8s %9s %14s  %s' % (
        'method', 'train s', 'err p50 rad', 'err p99 rad', 'gripper', 'familiar',
        'step p50/p99', 'task metric (bound)')]
    for method, f in results.items():
        task = ', '.join('%s %.3g%s' % (name, value, ' (<= %g%s)' % (
            bounds[name], '' if value <= bounds[name] else ' FAILS')
            if bounds and name in bounds else '') for name, value in f.get('task', {}).items())
        lines.append('%-6s %8.1f %12.4f %12.4f %7.1f%% %8.1f%% %6.3f/%.3f ms  %s' % (
            method, f['train_s'], f['error_p50_rad'], f['error_p99_rad'],
            100 * f['gripper_agreement'], 100 * f['familiar'], f['step_p50_ms'],
            f['step_p99_ms'], task or '(task unknown: no metric)'))
    return lines
