"""The `netbed` command: build, control and remove a two-host network test bed (bed.py).

    tools/netbed/netbed up [--seed 1]                   # as root; prints the hosts' addresses
    tools/netbed/netbed set --delay-ms 50 --jitter-ms 10 --loss 0.01 [--direction to-robot]
    tools/netbed/netbed cut [--direction to-operator]; tools/netbed/netbed restore
    tools/netbed/netbed status                          # settings and counters per direction
    tools/netbed/netbed exec robot roscore              # ROS_IP set to the robot's address
    tools/netbed/netbed exec operator rostopic list     # master: the robot's, port 11311
    tools/netbed/netbed lockdown                        # load config/nftables/robopuppet.nft
    tools/netbed/netbed unlock                          # remove it again
    tools/netbed/netbed down                            # idempotent; also after a crash
    tools/netbed/netbed list; tools/netbed/netbed gc    # beds; remove beds of dead test runs

--name NAME (or $NETBED) picks the bed: default 'rpbed'. Tests use their own names
(rp<pid>), so they never collide with a bed made by hand. `exec` sets ROS_IP to the host's
address, unsets ROS_HOSTNAME, and sets ROS_MASTER_URI to http://ROBOT_ADDRESS:11311 unless it
names a master other than localhost already.
"""
import argparse
import os
import sys

from netbed import bed as bedlib
from netbed import netns

ROOT = os.path.dirname(bedlib.TOOLS_DIR)
RULES = os.path.join(ROOT, 'catkin_ws', 'src', 'robopuppet', 'config', 'nftables',
                     'robopuppet.nft')
DEFAULT_NAME = 'rpbed'
DEFAULT_MASTER_PORT = 11311


def show_status(bed):
    status = bed.status()
    print('bed %s: forwarder pid %d, CPU %.2f s, unroutable %d'
          % (bed.name, status['pid'], status['cpu_s'], status['unroutable']))
    for direction, link in status['links'].items():
        print('  %-11s delay %.1f ms  jitter +-%.1f ms  loss %.3f  %s  | offered %d  released %d'
              '  lost %d  cut %d  overflow %d  in flight %d'
              % (direction, link['delay_ms'], link['jitter_ms'], link['loss'],
                 'CUT' if link['is_cut'] else 'up ', link['offered'], link['released'],
                 link['lost'], link['cut'], link['overflow'], link['in_flight']))


def cmd_up(bed, args):
    bed.up(seed=args.seed)
    if any(v is not None for v in (args.delay_ms, args.jitter_ms, args.loss)):
        bed.set(delay_ms=args.delay_ms, jitter_ms=args.jitter_ms, loss=args.loss)
    print('bed %s up (seed %s)' % (bed.name, args.seed))
    for host in bedlib.HOSTS:
        print('  %-9s namespace %-12s address %s' % (host, bed.namespace(host),
                                                     bed.address(host)))
    print('  network   namespace %s (forwarder pid %s)'
          % (bed.namespace(bedlib.NETWORK), bed.state().get('forwarder_pid')))


def cmd_exec(bed, args):
    if not args.argv:
        raise SystemExit('netbed exec: give a command to run')
    if not netns.exists(bed.namespace(args.host)):
        raise SystemExit('netbed: bed %s is not up' % bed.name)
    argv = bed.command(args.host, args.argv)
    env = bed.host_env(args.host)
    master = env.get('ROS_MASTER_URI', '')
    if not master or '//localhost' in master or '//127.' in master:
        # Inside the bed "this machine" is a host of its own: the master is the robot's.
        env['ROS_MASTER_URI'] = 'http://%s:%d' % (bed.address('robot'), DEFAULT_MASTER_PORT)
    os.execvpe(argv[0], argv, env)


def cmd_lockdown(bed, args):
    with open(args.rules) as f:
        text = f.read()
    for host in ('operator', 'robot'):
        bedlib.load_rules(bed, host, text)
    print('rule set %s loaded on operator and robot of bed %s' % (args.rules, bed.name))


def cmd_unlock(bed, _args):
    for host in ('operator', 'robot'):
        os.spawnvp(os.P_WAIT, 'ip', bed.command(host, ['nft', 'flush', 'ruleset']))
    print('rule sets removed from operator and robot of bed %s' % bed.name)


def main(argv=None):
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument('--name', default=os.environ.get('NETBED', DEFAULT_NAME),
                        help='bed name (default $NETBED or %s)' % DEFAULT_NAME)
    parser = argparse.ArgumentParser(
        prog='netbed', description=__doc__.splitlines()[0],
        formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    sub = parser.add_subparsers(dest='command', required=True)
    directions = ('both',) + ('to-robot', 'to-operator')
    up = sub.add_parser('up', parents=[common], help='build the bed (replaces one of that name)')
    up.add_argument('--seed', default='1', help='seed of the loss and jitter generators')
    setp = sub.add_parser('set', parents=[common], help='set delay, jitter and loss')
    for p in (up, setp):
        p.add_argument('--delay-ms', type=float, help='one-way delay, ms')
        p.add_argument('--jitter-ms', type=float, help='+- uniform jitter, ms')
        p.add_argument('--loss', type=float, help='fraction of packets lost, 0-1')
    setp.add_argument('--direction', choices=directions, default='both')
    for name, text in (('cut', 'cut the link'), ('restore', 'restore the link')):
        sub.add_parser(name, parents=[common], help=text).add_argument(
            '--direction', choices=directions, default='both')
    sub.add_parser('status', parents=[common], help='settings and counters')
    sub.add_parser('down', parents=[common], help='remove the bed (idempotent)')
    ex = sub.add_parser('exec', parents=[common], help='run a command on a host')
    ex.add_argument('host', choices=tuple(bedlib.HOSTS) + (bedlib.NETWORK,))
    ex.add_argument('argv', nargs=argparse.REMAINDER)
    lock = sub.add_parser('lockdown', parents=[common],
                          help='load the nftables rule set on operator and robot')
    lock.add_argument('--rules', default=RULES, help='rule set (default: %(default)s)')
    sub.add_parser('unlock', parents=[common], help='flush the rule sets again')
    sub.add_parser('list', help='list the beds')
    sub.add_parser('gc', help='remove beds whose owning process has died')
    args = parser.parse_args(argv)

    if os.geteuid() != 0:
        raise SystemExit('netbed: network namespaces need root')
    if args.command == 'list':
        for name in bedlib.beds():
            print(name, bedlib.Bed(name).state())
        return 0
    if args.command == 'gc':
        print('removed: %s' % (' '.join(bedlib.gc()) or 'none'))
        return 0
    bed = bedlib.Bed(args.name)
    try:
        if args.command == 'up':
            cmd_up(bed, args)
        elif args.command == 'down':
            bed.down()
            print('bed %s down' % bed.name)
        elif args.command == 'set':
            bed.set(args.direction, args.delay_ms, args.jitter_ms, args.loss)
            show_status(bed)
        elif args.command in ('cut', 'restore'):
            getattr(bed, args.command)(args.direction)
            show_status(bed)
        elif args.command == 'status':
            show_status(bed)
        elif args.command == 'exec':
            cmd_exec(bed, args)
        elif args.command == 'lockdown':
            cmd_lockdown(bed, args)
        elif args.command == 'unlock':
            cmd_unlock(bed, args)
    except (bedlib.BedError, netns.NetnsError, ValueError) as err:
        print('netbed: %s' % err, file=sys.stderr)
        return 1
    return 0
