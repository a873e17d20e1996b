"""The terminal command replay: play a recorded episode back onto the robot or into the puppet.

    rosrun robopuppet replay EPISODE [--speed S] [--side L|R|LR] [--arms left,right]
                             [--zones FILE]
    rosrun robopuppet replay EPISODE --into puppet [--side L|R|LR] [--speed S]

Onto the robot (default) it drives robopuppet.episodes.replay through
robopuppet.episodes.robot_player; into the puppet, robopuppet.episodes.puppet_playback through
robopuppet.episodes.puppet_player. Exit code 0: the episode played to its end; 1: stopped by a
stop rule; 2: refused or failed (a message says why).

Onto the robot the replay keeps Baxter's arms out of the keep-out zones (docs/zones.md): a
command that would take an arm into one stops the replay unsent (exit 1, naming zone, link and
arm). The zones: --zones FILE (/dev/null, an empty file: none); by default those of the running
arm controllers, their zones_file parameters (/arm_L/zones_file, /arm_R/zones_file, set by
arm.launch; '' for none), all of them when the two differ; with neither set, the package's
config/zones.yaml. A bad zone file refuses the replay (exit 2).
"""
import argparse
import sys

import rospy

from robopuppet import baxter_description
from robopuppet import interface as ifc
from robopuppet.episodes import (export, export_cli, export_files, puppet_playback,
                                 puppet_player, replay, robot_player)
from robopuppet.episodes.metadata import EpisodeError, episode_paths, read_metadata
from robopuppet.episodes.recording import parse_sides


def main(argv=None):
    """Parse the arguments, replay the episode, exit with the exit code."""
    parser = argparse.ArgumentParser(prog='replay', description=__doc__.split('\n')[0])
    parser.add_argument('episode', help='a name in the episodes directory, or a .bag/.yaml')
    parser.add_argument('--into', choices=('robot', 'puppet'), default='robot',
                        help="robot: Baxter's recorded commands (default); puppet: the "
                             "recorded puppet angles as setpoints into the puppet in hold")
    parser.add_argument('--speed', type=float, default=1.0,
                        help='speed factor, 0 < S <= %g (default 1; the joints never exceed '
                             'their velocity limits)' % replay.MAX_SPEED)
    parser.add_argument('--side', help="puppet sides whose button 1 stops the replay; into "
                                       "the puppet, the arms played (default: the episode's)")
    parser.add_argument('--arms', help="Baxter arms to replay, e.g. right or left,right "
                                       "(default: those the episode commands)")
    parser.add_argument('--zones', metavar='FILE',
                        help="keep-out zone file the robot's arms keep out of (/dev/null: none; "
                             "default: the running arm controllers' zones_file, all of them "
                             "when arm_L's and arm_R's differ, else the package's "
                             "config/zones.yaml)")
    args = parser.parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    for given, what in ((args.arms, '--arms names Baxter arms'),
                        (args.zones, '--zones binds Baxter arms')):
        if given is not None and args.into == 'puppet':
            parser.error('%s: not with --into puppet' % what)

    def say(text):
        print('replay: %s' % text, file=sys.stderr, flush=True)
    try:
        bag_path, yaml_path = episode_paths(export_cli.resolve(args.episode))
        sides = parse_sides(args.side or ''.join(
            read_metadata(yaml_path).get('sides') or ifc.PUPPET_SIDES))
        say('reading %s' % bag_path)
        recording = export.collect(export_files.read_messages(bag_path, export.episode_topics()))
        if args.into == 'puppet':
            core = puppet_playback.PuppetPlayback(puppet_playback.puppet_paths(
                recording, sides), args.speed, 1.0 / puppet_player.RATE_HZ)
        else:
            arms = args.arms.replace(',', ' ').split() if args.arms else None
            limits = {s: baxter_description.arm_limits(s) for s in ifc.BAXTER_SIDES}
            paths, grips = replay.episode_script(recording, arms)
            replay.check_speed(args.speed)
    except (EpisodeError, ValueError) as error:
        say('failed: %s' % error)
        sys.exit(2)
    rospy.init_node('replay', anonymous=True)
    if args.into == 'robot':   # the zones' default comes from the parameter server
        try:
            guards = robot_player.keepout_zones(args.zones, say)
        except ValueError as error:   # a bad zone file (ZoneFileError) or robot description
            say('refused: %s' % error)
            sys.exit(2)
        core = replay.Replay(paths, grips, limits, args.speed, 1.0 / robot_player.RATE_HZ,
                             guards=guards)
    node = (puppet_player.PuppetPlayer(core, say) if args.into == 'puppet'
            else robot_player.RobotPlayer(core, sides, say))
    sys.exit(node.run())
