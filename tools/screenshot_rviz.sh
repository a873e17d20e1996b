#!/usr/bin/env bash
# Screenshot RViz showing the Baxter stand-in (launch/baxter_sim.launch) on a virtual screen.
#   tools/screenshot_rviz.sh [OUT.png] [WAIT_S]
# Starts its own roscore on a free port, waits WAIT_S seconds (default 25) for RViz to draw,
# grabs the whole screen with ImageMagick's `import`, and stops everything it started.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="$(realpath -m "${1:-${TMPDIR:-/tmp}/baxter_rviz.png}")"
WAIT_S="${2:-25}"
# shellcheck disable=SC1091
. "$ROOT/tools/env.sh"
PORT="$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
export ROS_MASTER_URI="http://localhost:$PORT" LIBGL_ALWAYS_SOFTWARE=1 OUT WAIT_S PORT
export ROS_HOME="${ROS_HOME:-$(mktemp -d)}"
exec xvfb-run -a -s "-screen 0 1400x900x24" bash -c '
  roslaunch -p "$PORT" robopuppet baxter_sim.launch >"$ROS_HOME/launch.log" 2>&1 &
  launch_pid=$!
  sleep "$WAIT_S"
  import -window root "$OUT"
  kill -INT "$launch_pid"
  wait "$launch_pid" || true
  echo "screenshot: $OUT (launch log: $ROS_HOME/launch.log)"'
