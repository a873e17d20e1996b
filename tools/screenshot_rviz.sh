#!/usr/bin/env bash
# Screenshot RViz showing the Baxter stand-in (launch/baxter_sim.launch) on a virtual screen.
#   tools/screenshot_rviz.sh [OUT.png] [WAIT_S]
# Starts its own roscore on a free port, waits WAIT_S seconds (default 25) for RViz to draw,
# grabs the whole screen with ImageMagick's `import`, and stops everything it started. ROS_HOME
# (logs, roscore's pid file) is a fresh temporary directory, removed at the end; the launch log
# is printed when the screenshot fails.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="$(realpath -m "${1:-${TMPDIR:-/tmp}/baxter_rviz.png}")"
WAIT_S="${2:-25}"
# shellcheck disable=SC1091
. "$ROOT/tools/env.sh"
PORT="$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
ROS_HOME="$(mktemp -d)"
trap 'rm -rf "$ROS_HOME"' EXIT
export ROS_MASTER_URI="http://localhost:$PORT" LIBGL_ALWAYS_SOFTWARE=1 OUT WAIT_S PORT ROS_HOME
export ROS_LOG_DIR="$ROS_HOME/log"
xvfb-run -a -s "-screen 0 1400x900x24" bash -c '
  roslaunch -p "$PORT" robopuppet baxter_sim.launch >"$ROS_HOME/launch.log" 2>&1 &
  launch_pid=$!
  sleep "$WAIT_S"
  status=0
  import -window root "$OUT" || status=$?
  kill -INT "$launch_pid"
  wait "$launch_pid" || true
  if [ "$status" -ne 0 ]; then
    echo "screenshot failed; launch log:" >&2
    cat "$ROS_HOME/launch.log" >&2
    exit "$status"
  fi
  echo "screenshot: $OUT"'
