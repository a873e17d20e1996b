"""The study runner's child processes: `roslaunch robopuppet input.launch` per puppet side,
and `rosrun robopuppet move_arms` bringing the arms to their start before a trial.

No ROS import: each is a child process, started with its arguments and stopped by its pid
(SIGINT, as Ctrl-C stops roslaunch: it stops its nodes in turn) and waited for.
"""
import os
import signal
import stat
import subprocess

STOP_WAIT_S = 15.0   # roslaunch's own SIGINT handling escalates within this; then SIGKILL
MOVE_ARMS = ['rosrun', 'robopuppet', 'move_arms']   # both arms to Baxter's neutral pose


def side_events(path, side):
    """Return a side's event source: a character device (a real device: every reader gets
    every event) for both sides, anything else (a FIFO prefix, a recording) as <path>_<side>."""
    try:
        if stat.S_ISCHR(os.stat(path).st_mode):
            return path
    except OSError:
        pass
    return '%s_%s' % (path, side)


def stop_process(process):
    """Stop a child by its pid (SIGINT), wait for it, SIGKILL after STOP_WAIT_S; return its
    exit code."""
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
    try:
        return process.wait(timeout=STOP_WAIT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        return process.wait()


def launch_command(device, side, events, extra=()):
    """Return the roslaunch command line of one side's input (events: the study's path for
    the device, '' for none)."""
    command = ['roslaunch', 'robopuppet', 'input.launch', 'device:=%s' % device,
               'arm_side:=%s' % side]
    if events:
        command.append('events:=%s' % side_events(events, side))
    return command + list(extra)


class InputProcesses:
    """The inputs running now, one roslaunch child per side. Args: extra (more arguments of
    input.launch, e.g. sim_puppet:=true), popen (subprocess.Popen; injectable for tests)."""

    def __init__(self, extra=(), popen=subprocess.Popen):
        self._extra, self._popen = list(extra), popen
        self._running = {}   # side -> Popen

    def start(self, device, events):
        """Stop what runs, then start `device` on each side of events {side: path or ''}.
        Returns the command lines started."""
        self.stop()
        commands = []
        for side, path in sorted(events.items()):
            command = launch_command(device, side, path, self._extra)
            self._running[side] = self._popen(command, stdin=subprocess.DEVNULL)
            commands.append(command)
        return commands

    def stop(self):
        """Stop every input by its pid (SIGINT) and wait for it; SIGKILL after STOP_WAIT_S.
        Returns the exit codes {side: code}."""
        codes = {side: stop_process(process) for side, process in sorted(self._running.items())}
        self._running = {}
        return codes

    def exited(self):
        """Return {side: exit code} of the inputs that ended by themselves."""
        return {side: p.poll() for side, p in self._running.items() if p.poll() is not None}


class ArmsMove:
    """move_arms as a child process, one at a time. Args: popen (injectable for tests)."""

    def __init__(self, popen=subprocess.Popen):
        self._popen, self._process = popen, None

    def start(self):
        """Stop a move that runs, then start move_arms; return its command line."""
        self.stop()
        self._process = self._popen(MOVE_ARMS, stdin=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                    universal_newlines=True)
        return list(MOVE_ARMS)

    def ended(self):
        """Return (exit code, its last line on stderr: why it stopped or was refused) once
        the move ended, else None."""
        if self._process is None or self._process.poll() is None:
            return None
        process, self._process = self._process, None
        lines = process.stderr.read().strip().splitlines()
        return process.returncode, lines[-1] if lines else ''

    def stop(self):
        """Stop a move that runs (Baxter holds where it is)."""
        if self._process is not None:
            stop_process(self._process)
            self._process = None
