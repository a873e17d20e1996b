#!/usr/bin/python3
"""Benchmark: the assist's learners: training time, inference per step, held-out accuracy.

Usage: benchmarks/bench_assist.py [--episodes 20,100] [--tasks carry_tray,hold_forearm]
                                  [--methods gmr,lwr] [--heldout 10] [--unfamiliar 5] [--seed 0]
(after `. tools/env.sh`; no ROS)

For each task and each training size, scripted demonstrations (assist.demonstration.demonstrate,
seeds from --seed) train each method (learners.train: the calibration fit and the final fit);
--heldout other demonstrations (seeds from 10000) are the held-out set. Printed per row:
training time (wall and this process's CPU), the follower's joint error p50/p99 over held-out
steps (the max over its 7 joints per step, rad), gripper agreement, familiar steps, the task
metric (tasks.metrics on the demonstrated leader and predicted follower, worst over the
held-out set, against the task's bounds), step() p50/p99 (ms, every held-out step, stepped as
the assist node steps it; the target is p99 <= 2 ms at 100 Hz; cpu99: its thread CPU time's
p99, without the waits for a core), and how long after an
unfamiliar motion (demonstration.unfamiliar, --unfamiliar seeds) departs from the follower's
start the prediction first becomes unfamiliar (worst over them; departure: the first step the
leader's tool point is DEPARTED_M from where it started). A seed whose demonstration cannot be
made (demonstration raises ValueError) is skipped and counted.
Wall time on a loaded machine holds waits for a core: the load average is printed.
"""
import argparse
import os
import time

import numpy as np

from robopuppet.assist import demonstration, learners, tasks, train

DEPARTED_M = 0.02
SKIPPED = []


def departure_s(demo, leader):
    """Return when the leader's tool point is first DEPARTED_M from where it started (s)."""
    tips = tasks.tip_positions(leader, getattr(demo, leader))
    moved = np.flatnonzero(np.linalg.norm(tips - tips[0], axis=1) >= DEPARTED_M)
    return demo.t[moved[0]] if len(moved) else demo.t[-1]


def made(make, key, seeds):
    """Return the demonstrations make(key, seed) of seeds, skipping (and noting) failures."""
    demos = []
    for seed in seeds:
        try:
            demos.append(make(key, seed))
        except ValueError as error:
            SKIPPED.append('%s seed %d: %s' % (key, seed, error))
    return demos


def unfamiliar_delay_s(predictor, key, seeds):
    """Return the worst delay (s) from an unfamiliar motion's departure to its first unfamiliar
    step, None when one never became unfamiliar."""
    worst = 0.0
    for demo in made(demonstration.unfamiliar, key, seeds):
        _, _, confidence = predictor.predict_demo(demo)
        departed = departure_s(demo, predictor.leader)
        late = np.flatnonzero((confidence < learners.CONFIDENCE_THRESHOLD) & (demo.t >= departed))
        if not len(late):
            return None
        worst = max(worst, demo.t[late[0]] - departed)
    return worst


def row(task, count, method, figures, train_wall_s, train_cpu_s, delay_s):
    metric = ', '.join('%s %.3g%s' % (name, value, '' if value <= task.bounds.get(name, np.inf)
                                       else ' FAILS') for name, value in figures['task'].items())
    return ('%-12s %5d %-4s %7.1f %7.1f %8.4f %8.4f %6.1f%% %7.1f%% %6.3f %6.3f %6.3f %7s  %s' % (
        task.key, count, method, train_wall_s, train_cpu_s, figures['error_p50_rad'],
        figures['error_p99_rad'], 100 * figures['gripper_agreement'], 100 * figures['familiar'],
        figures['step_p50_ms'], figures['step_p99_ms'], figures['step_cpu_p99_ms'],
        'never' if delay_s is None else '%.2f' % delay_s, metric))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--episodes', default='20,100')
    parser.add_argument('--tasks', default=','.join(sorted(tasks.TASKS)))
    parser.add_argument('--methods', default=','.join(learners.METHODS))
    parser.add_argument('--heldout', type=int, default=10)
    parser.add_argument('--unfamiliar', type=int, default=5)
    parser.add_argument('--seed', type=int, default=0)
    args = parser.parse_args()
    print('load average at start: %.2f %.2f %.2f' % os.getloadavg())
    print('%-12s %5s %-4s %7s %7s %8s %8s %7s %8s %6s %6s %6s %7s  %s' % (
        'task', 'demos', 'meth', 'train s', 'cpu s', 'err p50', 'err p99', 'gripper',
        'familiar', 'step50', 'step99', 'cpu99', 'unfam s', 'task metric (worst held-out)'))
    for key in args.tasks.split(','):
        task = tasks.TASKS[key]
        held = made(demonstration.demonstrate, key, range(10000, 10000 + args.heldout))
        counts = [int(c) for c in args.episodes.split(',')]
        every = made(demonstration.demonstrate, key, range(args.seed, args.seed + max(counts)))
        for count in counts:
            demos = every[:count]
            for method in args.methods.split(','):
                wall, cpu = time.perf_counter(), time.process_time()
                predictor = learners.train(demos, method, task.leader, task.follower,
                                           task.text, args.seed)
                wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
                figures = train.evaluate(predictor, held, lambda left_q, right_q, key=key:
                                         tasks.metrics(key, left_q, right_q), len(held))
                delay = unfamiliar_delay_s(predictor, key, range(20000, 20000 + args.unfamiliar))
                print(row(task, len(demos), method, figures, wall, cpu, delay), flush=True)
    print('bounds: %s' % '; '.join('%s %s' % (k, tasks.TASKS[k].bounds)
                                   for k in args.tasks.split(',')))
    print('skipped: %s' % ('; '.join(SKIPPED) or 'none'))
    print('load average at end: %.2f %.2f %.2f' % os.getloadavg())


if __name__ == '__main__':
    main()
