"""The study command's arguments and exit codes, and the runner's settings from its parameters.

Pure: `rosrun robopuppet study` with --participant starts a study at once and exits when it
ends; without, it is the node that study.launch runs, waiting for the GUI's Start.
"""
import argparse
import os
import sys

from robopuppet import interface
from robopuppet.study import results

EXIT_DONE, EXIT_STOPPED, EXIT_USAGE, EXIT_BUSY = 0, 1, 2, 3
EPILOG = """exit codes: 0 the study is done (results written, summary made), 1 it was stopped or
failed (the reason is printed), 2 bad arguments or a study that cannot start (a bad
participant id, a device without event path), 3 another study runner serves %s.
The results go to RESULTS_DIR/trials.csv and questionnaire.csv; summarise them again
with `rosrun robopuppet study_summary RESULTS_DIR`.""" % interface.STUDY_START
DEFAULTS = {'study': 'study', 'devices': list(interface.STUDY_DEVICES),
            'tasks': list(interface.STUDY_TASKS), 'practice': 1, 'trials': 1, 'seed': 0,
            'trial_timeout': 0.0, 'ready_timeout': 60.0, 'results_dir': '', 'events': {},
            'sim_puppet': False, 'input_args': []}


def names(text):
    """Return a comma-separated list as a list (a YAML list passes through)."""
    if isinstance(text, (list, tuple)):
        return [str(n).strip() for n in text if str(n).strip()]
    return [n.strip() for n in str(text).split(',') if n.strip()]


def parser():
    """Return the study command's argument parser."""
    made = argparse.ArgumentParser(
        prog='study', epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
        description='Run a RoboPuppet user study: each device in a balanced Latin-square '
        'order, practice trials first, then the trials, then the NASA-TLX and SUS '
        'questionnaire (the GUI\'s study tab, or the simulated participant). Without '
        '--participant, wait for the GUI\'s Start. Unset options take the node\'s '
        '~parameters (config/study.yaml, study.launch).')
    made.add_argument('--participant', help='the participant id (letters, digits, - and _)')
    made.add_argument('--devices', type=names, help='comma-separated, of %s'
                      % ', '.join(interface.STUDY_DEVICES))
    made.add_argument('--tasks', type=names, help='comma-separated, of %s'
                      % ', '.join(interface.STUDY_TASKS))
    made.add_argument('--practice', type=int, help='practice trials per task and device (1)')
    made.add_argument('--trials', type=int, help='trials per task and device (1)')
    made.add_argument('--seed', type=int, help="the study's seed of all targets (0)")
    made.add_argument('--study', help="the study's name (its results folder; 'study')")
    made.add_argument('--results-dir', dest='results_dir',
                      help='default $ROS_HOME/robopuppet/studies/STUDY')
    made.add_argument('--trial-timeout', dest='trial_timeout', type=float,
                      help="s per trial; 0: each task's own timeout")
    return made


def settings(params, args=None):
    """Return the runner's settings: DEFAULTS, then params (the node's ~parameters), then the
    command's arguments that were given.

    Raises:
        ValueError: a count, timeout or the events are of the wrong kind.
    """
    merged = dict(DEFAULTS)
    merged.update({k: v for k, v in params.items() if k in DEFAULTS})
    if args is not None:
        merged.update({k: v for k, v in vars(args).items() if k in DEFAULTS and v is not None})
    merged['devices'], merged['tasks'] = names(merged['devices']), names(merged['tasks'])
    for key in ('practice', 'trials', 'seed'):
        merged[key] = int(merged[key])
    for key in ('trial_timeout', 'ready_timeout'):
        merged[key] = float(merged[key])
        if merged[key] < 0:
            raise ValueError('~%s must be 0 or more, got %s' % (key, merged[key]))
    if not isinstance(merged['events'], dict):
        raise ValueError('~events must be a dictionary {device: path}, got %r'
                         % (merged['events'],))
    merged['events'] = {str(k): os.path.expanduser(str(v or ''))
                        for k, v in merged['events'].items()}
    if not merged['results_dir']:
        ros_home = os.environ.get('ROS_HOME') or os.path.expanduser('~/.ros')
        merged['results_dir'] = results.default_results_dir(ros_home, merged['study'])
    return merged


def exit_code(error, phase):
    """Return the command's exit code: a study refused at start, done, or stopped."""
    if error:
        return EXIT_USAGE
    return EXIT_DONE if phase == 'done' else EXIT_STOPPED


def leave(code, text=''):
    """Exit with `code`, saying `text` (when any) on stderr."""
    if text:
        print('study: %s' % text, file=sys.stderr)
    sys.exit(code)
