"""Unit tests of study.input_launch: each side's roslaunch command, stopped by its pid."""
import os
import subprocess
import sys

from robopuppet.study import input_launch


def test_a_fifo_prefix_gets_the_side_and_a_character_device_is_shared(tmp_path):
    assert input_launch.side_events(str(tmp_path / 'keyboard'), 'L') == str(
        tmp_path / 'keyboard') + '_L'
    assert input_launch.side_events('/dev/null', 'R') == '/dev/null'   # a character device


def test_the_command_names_device_side_events_and_extra_arguments():
    assert input_launch.launch_command('marker', 'R', '', ['sim_puppet:=true']) == [
        'roslaunch', 'robopuppet', 'input.launch', 'device:=marker', 'arm_side:=R',
        'sim_puppet:=true']
    assert input_launch.launch_command('keyboard', 'L', '/tmp/kb')[-1] == 'events:=/tmp/kb_L'


def test_inputs_are_started_per_side_and_stopped_by_sigint_and_waited_for(tmp_path):
    started = []
    # a stand-in for roslaunch: exits 7 on SIGINT, as a program that handles Ctrl-C
    script = ('import signal, sys, time\n'
              'signal.signal(signal.SIGINT, lambda *a: sys.exit(7))\n'
              'open(sys.argv[1], "w").close()\n'
              'time.sleep(60)\n')

    def popen(command, **kwargs):
        started.append(command)
        marker = str(tmp_path / command[4])
        process = subprocess.Popen([sys.executable, '-c', script, marker], **kwargs)
        while not os.path.exists(marker):   # its handler is set
            assert process.poll() is None
        return process

    inputs = input_launch.InputProcesses(['sim_puppet:=true'], popen=popen)
    inputs.start('keyboard', {'R': '/tmp/kb', 'L': '/tmp/kb'})
    assert [c[4] for c in started] == ['arm_side:=L', 'arm_side:=R']
    assert inputs.exited() == {}
    assert inputs.stop() == {'L': 7, 'R': 7}
    assert inputs.stop() == {}


def test_a_move_reports_its_exit_and_last_line_once_and_is_stopped_by_sigint(tmp_path):
    def popen_with(code):
        def popen(command, **kwargs):
            assert command == input_launch.MOVE_ARMS
            return subprocess.Popen([sys.executable, '-c', code], **kwargs)
        return popen

    move = input_launch.ArmsMove(popen_with(
        'import sys; print("move_arms: moving slowly", file=sys.stderr); '
        'print("move_arms: stopped: button 1 pressed", file=sys.stderr); sys.exit(1)'))
    assert move.ended() is None       # nothing started
    move.start()
    while (ended := move.ended()) is None:
        pass
    assert ended == (1, 'move_arms: stopped: button 1 pressed') and move.ended() is None
    started = tmp_path / 'started'
    move = input_launch.ArmsMove(popen_with(
        'import signal, sys, time\n'
        'signal.signal(signal.SIGINT, lambda *a: sys.exit(7))\n'
        'open(%r, "w").close()\n'
        'time.sleep(60)\n' % str(started)))
    move.start()
    while not started.exists():
        pass
    assert move.ended() is None      # still moving
    move.stop()
    assert move.ended() is None      # stopped: nothing to report
