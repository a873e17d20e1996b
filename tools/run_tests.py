#!/usr/bin/python3
"""Run RoboPuppet's tests: pytest unit tests, the two-host network tests, then every rostest file.

rostest starts a private roscore on a free port for each file, so runs never collide. The
network tests (tests/network, pytest) build their own two-host test bed in network namespaces
(tools/netbed) with a roscore inside it; they need root and are skipped, saying why, without.
Every master and node of the tests gets ROS_IP=127.0.0.1 (and no ROS_HOSTNAME), so no test
depends on this machine's host name resolving; the network tests set each host's own address.

Usage: run_tests.py [unit|network|integration|all] [NAME ...]
NAME filters the integration .test files (substring match), or with scope network the network
tests (pytest -k NAME). The unit tests run on every core (pytest-xdist). Scope unit leaves out
the unit tests marked slow (heavy property tests): the quick loop; all runs them. Prints one closing line, 'N passed, N failed in M min S s' and each
part's time, and exits non-zero when anything failed.
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PKG = os.path.join(ROOT, 'catkin_ws', 'src', 'robopuppet')
UNIT_DIR = os.path.join(PKG, 'tests', 'unit')
INTEGRATION_DIR = os.path.join(PKG, 'tests', 'integration')
NETWORK_DIR = os.path.join(PKG, 'tests', 'network')


def junit_counts(path):
    """Return (passed, failed) from a JUnit XML file; (0, 1) if it is missing or unreadable."""
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError):
        return 0, 1
    suites = [root] if root.tag == 'testsuite' else root.findall('testsuite')
    total = failed = skipped = 0
    for suite in suites:
        total += int(suite.get('tests', 0))
        failed += int(suite.get('failures', 0)) + int(suite.get('errors', 0))
        skipped += int(suite.get('skipped', 0))
    return total - failed - skipped, failed


def run_unit(work_dir, quick=False):
    """Run the pytest unit tests (quick: not those marked slow); return (passed, failed)."""
    xml = os.path.join(work_dir, 'unit.xml')
    print('[test] unit tests (pytest%s)' % (
        ', without the slow property tests: ./test.sh runs them' if quick else ''), flush=True)
    cmd = [sys.executable, '-m', 'pytest', UNIT_DIR, '-q', '-p', 'no:cacheprovider',
           '-n', 'auto', '--junitxml', xml] + (['-m', 'not slow'] if quick else [])
    code = subprocess.call(cmd, cwd=ROOT)
    passed, failed = junit_counts(xml)
    if code != 0 and failed == 0:
        failed = 1  # pytest itself failed (collection error, crash)
    return passed, failed


def run_network(names, work_dir):
    """Run the two-host network tests (pytest, network namespaces); return (passed, failed)."""
    xml = os.path.join(work_dir, 'network.xml')
    print('[test] network tests (pytest, two hosts in network namespaces)', flush=True)
    cmd = [sys.executable, '-m', 'pytest', NETWORK_DIR, '-q', '-rs', '-p', 'no:cacheprovider',
           '--junitxml', xml, '--basetemp', os.path.join(work_dir, 'network')]
    if names:
        cmd += ['-k', ' or '.join(names)]
    code = subprocess.call(cmd, cwd=ROOT)
    passed, failed = junit_counts(xml)
    if code == 5:  # pytest: no test matched the names
        return 0, 0
    if code != 0 and failed == 0:
        failed = 1  # pytest itself failed (collection error, crash)
    return passed, failed


def rostest_counts(output):
    """Return (passed, failed) from rostest's SUMMARY blocks, one per <test> of a file."""
    tests = [int(n) for n in re.findall(r'\* TESTS: (\d+)', output)]
    bad = sum(int(n) for n in re.findall(r'\* (?:ERRORS|FAILURES): (\d+)', output))
    if not tests:
        return 0, 1
    return max(sum(tests) - bad, 0), max(bad, 1 if 'RESULT: FAIL' in output else 0)


def run_integration(names, work_dir):
    """Run each matching rostest file (rostest gives each its own roscore port).

    Returns:
        (passed, failed)
    """
    files = sorted(glob.glob(os.path.join(INTEGRATION_DIR, '*.test')))
    if names:
        files = [f for f in files if any(n in os.path.basename(f) for n in names)]
    passed = failed = 0
    for path in files:
        name = os.path.basename(path)
        log = os.path.join(work_dir, name + '.log')
        print('[test] rostest %s' % name, flush=True)
        start = time.monotonic()
        # Each file gets its own ROS_HOME: live ini files and logs never leak between tests.
        env = dict(os.environ, ROS_HOME=os.path.join(work_dir, name + '.ros_home'))
        with open(log, 'w') as out:
            code = subprocess.call(['rostest', '--text', 'robopuppet', name],
                                   stdout=out, stderr=subprocess.STDOUT, cwd=ROOT, env=env)
        with open(log) as out:
            output = out.read()
        p, f = rostest_counts(output)
        if code != 0 and f == 0:
            f = 1
        passed += p
        failed += f
        verdict = 'ok' if f == 0 else 'FAILED (log: %s)' % log
        print('[test]   %d passed, %d failed in %.0f s: %s'
              % (p, f, time.monotonic() - start, verdict), flush=True)
        if f:
            print(output[-6000:])
    return passed, failed


def minutes(elapsed_s):
    """Return a duration as 'M min S s'."""
    return '%d min %02d s' % divmod(round(elapsed_s), 60)


def main():
    args = sys.argv[1:]
    scope = (args.pop(0) if args and args[0] in ('unit', 'network', 'integration', 'all')
             else 'all')
    work_dir = tempfile.mkdtemp(prefix='robopuppet-tests-')
    os.environ['ROS_HOME'] = os.path.join(work_dir, 'ros_home')
    os.environ['ROS_LOG_DIR'] = os.path.join(work_dir, 'ros_log')
    # Every test master and node is reached at 127.0.0.1: never by this machine's host name.
    os.environ['ROS_IP'] = '127.0.0.1'
    os.environ.pop('ROS_HOSTNAME', None)
    parts = []
    if scope in ('unit', 'all') and not args:
        parts.append(('unit', lambda: run_unit(work_dir, quick=scope == 'unit')))
    if scope == 'network' or (scope == 'all' and not args):
        parts.append(('network', lambda: run_network(args, work_dir)))
    if scope in ('integration', 'all'):
        parts.append(('integration', lambda: run_integration(args, work_dir)))
    passed = failed = 0
    times = []
    start = time.monotonic()
    for name, run in parts:
        part_start = time.monotonic()
        p, f = run()
        passed, failed = passed + p, failed + f
        times.append('%s %s' % (name, minutes(time.monotonic() - part_start)))
    if failed:
        print('[test] logs in %s' % work_dir)
    else:
        shutil.rmtree(work_dir, ignore_errors=True)
    print('%d passed, %d failed in %s (%s)'
          % (passed, failed, minutes(time.monotonic() - start), ', '.join(times)))
    return 1 if failed or passed == 0 else 0


if __name__ == '__main__':
    sys.exit(main())
