#!/usr/bin/python3
"""The operator's hand on the simulated puppet, for the two-host teleoperation tests: run on the
operator host (child process; rospy inits once per process), driven through a command file.

    puppet_hand.py SIDE COMMAND_FILE

It polls COMMAND_FILE for new lines, each a JSON object {"id": N, "op": OP, ...}, carries them out
in order and reports on stdout, one JSON object per line: first {"ready": true}, then per command
{"done": N, ...} (or {"failed": N, "error": text}), and for every hand pose it sets
{"hand": [7 rad], "t": time.time()}. Ops:

    calibrate  pose        sweep the quadrature joints through their index marks, end at pose
    press      button      press a user button until the puppet reports it, then release
    hand       pose        set the hand's pose
    sine       pose joints amplitude_rad period_s duration_s
                           move the listed joints of the hand on a sine around pose at 50 Hz

The teleoperation steps are teleop_harness's (tests/integration), the same as in main_sim's test.
"""
import json
import math
import os
import sys
import time

import rospy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..',
                                'integration'))
import teleop_harness  # noqa: E402

HAND_PERIOD_S = 0.02


def report(**fields):
    print(json.dumps(fields), flush=True)


def set_hand(puppet, pose):
    puppet.hand(pose)
    report(hand=list(pose), t=time.time())


def sine(puppet, pose, joints, amplitude_rad, period_s, duration_s):
    t0 = time.monotonic()
    while time.monotonic() - t0 < duration_s and not rospy.is_shutdown():
        phase = 2 * math.pi * (time.monotonic() - t0) / period_s
        moved = list(pose)
        for j in joints:
            moved[j] = pose[j] + amplitude_rad * math.sin(phase)
        set_hand(puppet, moved)
        time.sleep(HAND_PERIOD_S)
    set_hand(puppet, pose)


def run(puppet, command):
    op = command['op']
    if op == 'calibrate':
        teleop_harness.calibrate(puppet, command['pose'])
        report(hand=list(command['pose']), t=time.time())
    elif op == 'press':
        puppet.press(command['button'], command.get('timeout_s', 15.0))
    elif op == 'hand':
        set_hand(puppet, command['pose'])
    elif op == 'sine':
        sine(puppet, command['pose'], command['joints'], command['amplitude_rad'],
             command['period_s'], command['duration_s'])
    else:
        raise ValueError('unknown op %r' % op)


def main(argv):
    side, command_file = argv
    rospy.init_node('puppet_hand_%s' % side, anonymous=True)
    puppet = teleop_harness.PuppetArm(side)
    puppet.end_piece(False)
    report(ready=True, node=rospy.get_name())
    done = 0
    while not rospy.is_shutdown():
        try:
            with open(command_file) as lines:
                commands = [json.loads(line) for line in lines if line.strip()]
        except OSError:
            commands = []
        for command in commands[done:]:
            try:
                run(puppet, command)
                report(done=command['id'], t=time.time())
            except (AssertionError, ValueError, KeyError) as err:
                report(failed=command['id'], error=str(err), t=time.time())
            done += 1
        time.sleep(0.05)
    return 0


if __name__ == '__main__':
    sys.exit(main(rospy.myargv(sys.argv)[1:]))
