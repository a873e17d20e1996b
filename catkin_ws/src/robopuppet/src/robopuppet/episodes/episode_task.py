"""The terminal command episodes set-task: set the task of recorded episodes.

    rosrun robopuppet episodes set-task EPISODE... --task TEXT

An EPISODE is given as to export: a name (looked up in $ROS_HOME/robopuppet/episodes/) or the
path of its .bag or .yaml. The task (recording.check_task: one printable line of at most
recording.TASK_MAX_CHARS characters; '' clears it) replaces the metadata's `task`, the rest of
the .yaml kept; the file is rewritten whole or not at all (metadata.write_metadata: a temporary
file renamed over it). An episode still being recorded (its .bag.active) is refused, as is a
.yaml that cannot be read; each episode on its own: the exit code is 1 if any was refused, 2
for a task that is not valid (nothing written).
"""
import argparse
import os
import sys

import yaml

from robopuppet.episodes import recording
from robopuppet.episodes.export_cli import resolve
from robopuppet.episodes.metadata import (EpisodeError, episode_paths, read_metadata,
                                          write_metadata)


def set_task(episode, task):
    """Write task (checked already) as the metadata's task of an episode argument; return the
    .yaml's path. A bag without a .yaml gets one with its name and task.

    Raises:
        EpisodeError: the episode is being recorded, has no bag, or its .yaml is no metadata.
        OSError, yaml.YAMLError: the .yaml cannot be read or written.
    """
    bag_path, yaml_path = episode_paths(resolve(episode))
    name = os.path.basename(bag_path)[:-len(recording.BAG)]
    if os.path.exists(bag_path[:-len(recording.BAG)] + recording.ACTIVE):
        raise EpisodeError('%s is still being recorded (%s exists): stop the recording first'
                           % (name, name + recording.ACTIVE))
    data = read_metadata(yaml_path) or {'name': name}
    data['task'] = task
    write_metadata(yaml_path, data)
    return yaml_path


def main(argv):
    """Set the task of the episodes on the command line (argv: after set-task); exit 0 when
    every one was written, 1 if any was refused, 2 for a task that is not valid."""
    parser = argparse.ArgumentParser(
        prog='episodes set-task', description="Set recorded episodes' task (what they "
        "demonstrate, for language-conditioned policies).")
    parser.add_argument('episodes', nargs='+', metavar='EPISODE',
                        help='a name in the default episodes folder, or a .bag or .yaml path')
    parser.add_argument('--task', required=True, metavar='TEXT',
                        help="the task, one line of at most %d printable characters ('' "
                        'clears it)' % recording.TASK_MAX_CHARS)
    args = parser.parse_args(argv)
    try:
        task = recording.check_task(args.task)
    except ValueError as error:
        parser.error(str(error))
    failed = False
    for episode in args.episodes:
        try:
            path = set_task(episode, task)
        except (EpisodeError, OSError, yaml.YAMLError) as error:
            print('episodes set-task: %s: %s' % (episode, error), file=sys.stderr)
            failed = True
            continue
        print('%s: task %s' % (path, repr(task) if task else 'cleared'))
    sys.exit(1 if failed else 0)
