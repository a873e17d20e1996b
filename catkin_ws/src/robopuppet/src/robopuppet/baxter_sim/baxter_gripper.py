"""Kinematic model of Baxter's electric gripper for the stand-in, and the commands it obeys.

Pure: every method that changes with time takes `now_s` (seconds, any monotonic origin).
"""
import json

from robopuppet.baxter_sim.baxter_refusals import CommandError, brief, finite

GRIPPER_OPEN = 100.0    # % of finger travel; 0 is closed
# Electric gripper parameters of the `configure` command (% of maximum), with the SDK's defaults.
GRIPPER_DEFAULTS = {'velocity': 50.0, 'moving_force': 40.0, 'holding_force': 30.0,
                    'dead_zone': 5.0}
# Longest command, args or sender text taken (characters). The SDK's are a few dozen; the state
# echoes command and sender 100 times a second, so a megabyte there would choke the publisher.
MAX_TEXT_CHARS = 4096


def approach(position, target, max_step, smoothing_factor, settle=0.0):
    """Return the next position: a fraction of the way to target, at most max_step; all the
    way when that would leave at most `settle` to go (a lag that ends, not one that creeps)."""
    step = (target - position) * smoothing_factor
    if abs(target - position - step) <= settle:
        step = target - position
    return position + max(-max_step, min(max_step, step))


def parse_args(command, args):
    """Return a gripper command's JSON args text as a dict ({} for blank text).

    Raises:
        CommandError: 'malformed args' when it is not a JSON object (also nested too deeply).
    """
    if not args.strip():
        return {}
    try:
        parsed = json.loads(args)
    except RecursionError as error:
        raise CommandError('gripper %s: args are nested too deeply: %s' % (
            brief(command), brief(args)), 'malformed args') from error
    except ValueError as error:
        raise CommandError('gripper %s: args are not JSON: %s' % (brief(command), brief(args)),
                           'malformed args') from error
    if not isinstance(parsed, dict):
        raise CommandError('gripper %s: args must be a JSON object, got %s' % (
            brief(command), brief(args)), 'malformed args')
    return parsed


class Gripper:
    """One electric gripper: position 0 (closed) ... 100 (open), moving at a finite speed.

    Args:
        max_speed_pct_s: speed at velocity parameter 100 (% of travel per second).
        calibrated: whether it starts calibrated (the real one does not after power-up).
    """

    def __init__(self, max_speed_pct_s, calibrated, now_s):
        self.max_speed_pct_s = max_speed_pct_s
        self.position = GRIPPER_OPEN
        self.speed_pct_s = 0.0
        self.target = GRIPPER_OPEN
        self.parameters = dict(GRIPPER_DEFAULTS)
        self.calibrated = calibrated
        self.calibrating = False
        self.error = False
        self.missed = False
        self.last_command = ('', '', 0)   # (command, sender, sequence), echoed in the state
        self.last_step_s = now_s

    @property
    def moving(self):
        return self.position != self.target

    def command(self, command, args, sender, sequence):
        """Handle an EndEffectorCommand; it is acknowledged even when refused.

        Args:
            command: 'go', 'calibrate', 'clear_calibration', 'reset', 'stop', 'configure',
                'reboot' or 'no_op'.
            args: the command's JSON argument text ('' for none).

        Raises:
            CommandError: unknown command, bad arguments, or go while uncalibrated; a command,
                args or sender longer than MAX_TEXT_CHARS is refused without acknowledgement.
        """
        if max(len(command), len(args), len(sender)) > MAX_TEXT_CHARS:
            raise CommandError('gripper command refused unacknowledged: command, args or sender '
                               'longer than %d characters (%d, %d, %d)' % (
                                   MAX_TEXT_CHARS, len(command), len(args), len(sender)),
                               'too long')
        self.last_command = (command, sender, sequence)
        args = parse_args(command, args)
        if command == 'go':
            if not self.calibrated:
                raise CommandError('gripper go refused: not calibrated (send calibrate first)',
                                   'not calibrated')
            if 'position' not in args:
                raise CommandError('gripper go needs {"position": 0..100}, got %s'
                                   % brief(args), 'malformed args')
            position = finite(args['position'], 'gripper go: position')
            self.target = min(GRIPPER_OPEN, max(0.0, position))
            self.missed = False
        elif command == 'configure':
            unknown = set(args) - set(GRIPPER_DEFAULTS)
            if unknown:
                raise CommandError('gripper configure: unknown parameters %s'
                                   % brief(sorted(unknown)), 'unknown parameter')
            values = {key: min(100.0, max(0.0, finite(value, 'gripper configure: ' + key)))
                      for key, value in args.items()}
            self.parameters.update(values)   # all or nothing
        elif command == 'calibrate':
            self.calibrated, self.calibrating = False, True
            self.target = GRIPPER_OPEN
        elif command in ('clear_calibration', 'reboot'):
            self.calibrated = self.calibrating = False
            self.target = self.position
            self.error = self.error and command != 'reboot'
        elif command == 'reset':
            self.error = False
        elif command == 'stop':
            self.target = self.position
            self.calibrating = False
        elif command != 'no_op':
            raise CommandError('gripper command %s is not supported by the electric gripper'
                               % brief(command), 'unknown command')

    def step(self, now_s, enabled):
        """Move toward the target until now_s (only while the robot is enabled)."""
        dt = now_s - self.last_step_s
        if dt <= 0.0:
            return
        self.last_step_s = now_s
        if not enabled:
            self.target = self.position
            self.speed_pct_s = 0.0
            self.calibrating = False
            return
        old = self.position
        max_step = self.max_speed_pct_s * self.parameters['velocity'] / 100.0 * dt
        self.position = approach(old, self.target, max_step, 1.0)
        self.speed_pct_s = (self.position - old) / dt
        if self.moving:
            return
        if self.calibrating:
            self.calibrated, self.calibrating = True, False
        elif old != self.position:
            # Nothing is ever grasped here: a close that reaches the end of travel missed.
            self.missed = self.position <= self.parameters['dead_zone']
