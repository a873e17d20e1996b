#!/usr/bin/env bash
# Install RoboPuppet's Debian packages (only the missing ones) and build the catkin workspace.
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
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q $missing
fi

echo "[setup] building catkin_ws"
cd "$ROOT/catkin_ws"
if ! out=$(catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release 2>&1); then
  echo "$out" | tail -40
  echo "[setup] catkin_make failed" >&2
  exit 1
fi
echo "[setup] workspace ready: source catkin_ws/devel/setup.bash"
