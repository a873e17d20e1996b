#!/usr/bin/python3
"""Report when this process is not scheduled on time: the machine is starved by other work.

    stall_probe.py [PERIOD_S [REPORT_S]]

Sleeps PERIOD_S (0.01 s) at a time and prints one JSON line {"t": time.time(), "stall_s": s}
whenever a sleep ends over REPORT_S (0.1 s) late; the first line is {"ready": true}. The network
tests run it beside the nodes of a host: a stall of this idle process means that the nodes,
which have more to do, were starved as long.
"""
import json
import sys
import time


def main(argv):
    period_s = float(argv[0]) if argv else 0.01
    report_s = float(argv[1]) if len(argv) > 1 else 0.1
    print(json.dumps({'ready': True}), flush=True)
    while True:
        before = time.monotonic()
        time.sleep(period_s)
        late_s = time.monotonic() - before - period_s
        if late_s > report_s:
            print(json.dumps({'t': time.time(), 'stall_s': round(late_s, 3)}), flush=True)


if __name__ == '__main__':
    try:
        sys.exit(main(sys.argv[1:]))
    except KeyboardInterrupt:
        sys.exit(0)
