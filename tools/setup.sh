#!/usr/bin/env bash
# Install RoboPuppet's Debian packages (only the missing ones), build the catkin workspace and
# install the one Python package Debian lacks (pyarrow, pinned) into it.
# Idempotent: a second run installs nothing and rebuilds only what changed.
# Sourced by run.sh and test.sh; also usable alone: bash tools/setup.sh
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Debian's ROS lives with /usr/bin/python3, whatever python3 the caller's PATH finds first.
export PATH="/usr/bin:/bin:$PATH"

wanted=$(grep -v '^#' "$ROOT/tools/debian-packages.txt" | tr '\n' ' ')
missing=""
for pkg in $wanted; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  [ "$status" = "install ok installed" ] || missing="$missing $pkg"
done
if [ -n "$missing" ]; then
  echo "[setup] installing Debian packages:$missing"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    if ! command -v sudo >/dev/null; then
      echo "[setup] these Debian packages are missing:$missing" >&2
      echo "[setup] install them as root (apt-get install ...), or install sudo, then run again" >&2
      exit 1
    fi
    SUDO="sudo"
  fi
  $SUDO apt-get update -q
  # sudo resets the environment, so the variable goes through env.
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q $missing
fi

echo "[setup] building catkin_ws"
cd "$ROOT/catkin_ws"
# One build at a time: a second run.sh or test.sh waits instead of racing in build/ and devel/.
exec 9>"$ROOT/catkin_ws/.build.lock"
flock 9
if ! out=$(catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release 2>&1); then
  echo "$out" | tail -40
  echo "[setup] catkin_make failed" >&2
  exit 1
fi
# The LeRobot export's Parquet writer: Debian 12 packages none, so a pinned pyarrow wheel from
# the Python package registry goes into the workspace, where lerobot_parquet.py finds it.
DEPS="$ROOT/catkin_ws/devel/python-deps"
PYARROW_VERSION=$(sed -n "s/^PYARROW_VERSION = '\([^']*\)'.*/\1/p" \
  "$ROOT/catkin_ws/src/robopuppet/src/robopuppet/episodes/lerobot_parquet.py")
if ! PYTHONPATH="$DEPS" /usr/bin/python3 -c "import sys, pyarrow
sys.exit(pyarrow.__version__ != '$PYARROW_VERSION')" 2>/dev/null; then
  echo "[setup] installing pyarrow $PYARROW_VERSION into $DEPS"
  rm -rf "$DEPS"
  /usr/bin/python3 -m pip install --quiet --disable-pip-version-check --no-deps \
    --root-user-action=ignore --only-binary=:all: --target "$DEPS" "pyarrow==$PYARROW_VERSION"
fi
flock -u 9
echo "[setup] workspace ready: source catkin_ws/devel/setup.bash"
