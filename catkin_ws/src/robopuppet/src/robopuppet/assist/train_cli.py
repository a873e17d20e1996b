"""The terminal command train_assist: train the assist's model from recorded episodes.

    rosrun robopuppet train_assist EPISODE...|DIR --out model.npz [--task TEXT]
        [--leader left|right] [--method gmr|lwr|best] [--holdout 0.25] [--seed 0]
        [--plot out.png]

An EPISODE is given as to export (a name in $ROS_HOME/robopuppet/episodes/, or a .bag or .yaml
path); a DIR stands for every .bag in it. Episodes whose task is not --task are left out; without
--task all must have the same task. The leader (the arm the nurse drives) defaults to the task's
(assist.tasks) or right; the follower is the other arm. Each method is trained on the training
episodes and evaluated on the held-out ones (a table: training time, follower joint error
p50/p99, gripper agreement, familiar steps, inference per step and, for a task assist.tasks
knows, its metric against its bounds); best keeps the better (train.choose says by what rule)
and writes it to --out (model_file). Exit code 0 when a model was written, 1 when none could be
(no episodes, too few to hold out, several tasks), 2 for bad arguments.
"""
import argparse
import collections
import sys

from robopuppet.assist import dataset, learners, model_file, tasks, train, train_plot
from robopuppet.interface import BAXTER_SIDES


def parse_args(argv):
    """Return the parsed command line (argv without the program)."""
    parser = argparse.ArgumentParser(
        prog='train_assist', description='Train the assist model (one Baxter arm predicted '
        'from the other) from recorded two-armed demonstrations.')
    parser.add_argument('episodes', nargs='+', metavar='EPISODE|DIR',
                        help='an episode name, .bag or .yaml path, or a folder of episodes')
    parser.add_argument('--out', required=True, help='the model file to write (.npz)')
    parser.add_argument('--task', help="only the episodes of this task (their metadata's)")
    parser.add_argument('--leader', choices=BAXTER_SIDES,
                        help="the arm the operator drives (default: the task's, else right)")
    parser.add_argument('--method', choices=learners.METHODS + ('best',), default='best')
    parser.add_argument('--holdout', type=float, default=0.25,
                        help='fraction of the episodes held out for evaluation (default 0.25)')
    parser.add_argument('--seed', type=int, default=0, help='of the split and the fits')
    parser.add_argument('--plot', metavar='PNG',
                        help='plot a held-out episode: demonstrated vs predicted follower')
    args = parser.parse_args(argv)
    if not 0.0 < args.holdout < 1.0:
        parser.error('--holdout must be between 0 and 1, got %g' % args.holdout)
    return args


def one_task(episodes, task):
    """Return the task text of the episodes.

    Raises:
        train.TrainError: they have several tasks and none was given.
    """
    counts = collections.Counter(e.task for e in episodes)
    if task is None and len(counts) > 1:
        raise train.TrainError('the episodes have %d tasks: choose one with --task (%s)' % (
            len(counts), '; '.join('%r: %d' % item for item in sorted(counts.items()))))
    return task if task is not None else next(iter(counts))


def run(args, say=print):
    """Train and write the model as args say; return the exit code."""
    known = tasks.by_text(args.task) if args.task else None
    leader = args.leader or (known.leader if known else 'right')
    follower = next(s for s in BAXTER_SIDES if s != leader)
    episodes, errors = dataset.read_episodes(args.episodes, leader, follower, args.task, say)
    if not episodes:
        say('error: no episodes to train on%s%s' % (
            ' with task %r' % args.task if args.task else '',
            ' (%d could not be read)' % len(errors) if errors else ''))
        return 1
    try:
        text = one_task(episodes, args.task)
        known = tasks.by_text(text)
        metrics = bounds = None
        if known is not None:
            bounds = dict(known.bounds)

            def metrics(left_q, right_q):
                return tasks.metrics(known.key, left_q, right_q)
        else:
            say('task %r is not one assist.tasks knows: no task metric' % text)
        methods = learners.METHODS if args.method == 'best' else (args.method,)
        predictor, results, reason, (training, held) = train.train_all(
            [e.demo for e in episodes], methods, leader, follower, text, args.holdout,
            args.seed, metrics, bounds, say)
    except (train.TrainError, learners.LearnerError) as error:
        say('error: %s' % error)
        return 1
    say('held-out evaluation (%d training, %d held-out episodes; follower %s, leader %s):'
        % (len(training), len(held), follower, leader))
    for line in train.table(results, bounds):
        say('  ' + line)
    if len(methods) > 1:
        say('kept %s: %s' % (predictor.method, reason))
    model_file.save(args.out, predictor, {
        'training_episodes': [episodes[i].name for i in training],
        'heldout_episodes': [episodes[i].name for i in held],
        'heldout': results, 'chosen_by': reason, 'task_bounds': bounds})
    say('wrote %s (%s)' % (args.out, predictor.method))
    if args.plot:
        name = episodes[held[0]].name
        train_plot.write_plot(args.plot, predictor, episodes[held[0]].demo,
                              '%s: %s predicted from %s, held-out %s'
                              % (predictor.method, follower, leader, name))
        say('wrote %s (held-out %s)' % (args.plot, name))
    return 0


def main(argv=None):
    """Run train_assist with argv (default sys.argv[1:]) and exit with its code."""
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        code = run(args, lambda text: print(text, flush=True))
    except OSError as error:
        print('error: %s' % error, file=sys.stderr)
        code = 1
    sys.exit(code)


if __name__ == '__main__':
    main()
