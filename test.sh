#!/usr/bin/env bash
# Set up (install Debian packages, build) and run every RoboPuppet test.
#   ./test.sh                     all tests
#   ./test.sh unit                pytest unit tests only, without those marked slow (the quick loop)
#   ./test.sh network [NAME]      two-host network tests only (as root; NAME: a pytest -k filter)
#   ./test.sh integration [NAME]  rostest files only (NAME: substring of a .test file name)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bash "$ROOT/tools/setup.sh"
. "$ROOT/tools/env.sh"
export LIBGL_ALWAYS_SOFTWARE=1
if [ -z "${DISPLAY:-}" ]; then
  # No screen: GUI and RViz tests run on a virtual one.
  exec xvfb-run -a -s "-screen 0 1600x1000x24" /usr/bin/python3 "$ROOT/tools/run_tests.py" "$@"
fi
exec /usr/bin/python3 "$ROOT/tools/run_tests.py" "$@"
