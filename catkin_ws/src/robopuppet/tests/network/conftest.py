"""pytest fixtures of the two-host network tests (RosBed: netbed_testing.py). Each bed is torn
down after its test (or module) whatever happens, and a test is skipped, saying why, when this
machine cannot create network namespaces (not root, no TUN device).

    ros_bed      a fresh bed for one test (no master yet: call ros_bed.roscore())
    shared_bed   one bed for a whole test module; start what the module shares in it
    link_bed     shared_bed with the link reset before the test: no delay, jitter, loss or cut
    master_bed   link_bed with a ROS master on the robot host (started once per module); the
                 processes a test starts are stopped after it
"""
import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import netbed_testing  # noqa: E402


def bed_or_skip(work_dir):
    try:
        netbed_testing.check_usable()
    except netbed_testing.BedUnavailable as err:
        pytest.skip(str(err))
    return netbed_testing.RosBed(work_dir)


@pytest.fixture
def ros_bed(tmp_path):
    with bed_or_skip(tmp_path) as bed:
        yield bed


@pytest.fixture(scope='module')
def shared_bed(tmp_path_factory):
    with bed_or_skip(tmp_path_factory.mktemp('bed')) as bed:
        yield bed


@pytest.fixture
def link_bed(shared_bed):
    shared_bed.reset_link()
    return shared_bed


@pytest.fixture
def master_bed(link_bed):
    if link_bed.master_uri is None:
        link_bed.roscore()
    first = len(link_bed.procs)
    yield link_bed
    link_bed.reset_link()
    link_bed.stop_started(first)
