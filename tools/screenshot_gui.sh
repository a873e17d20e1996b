#!/usr/bin/env bash
# Screenshot the RoboPuppet GUI (gui_R) while the simulated system runs, on a virtual screen.
#   tools/screenshot_gui.sh [--feel] [OUT_DIR]
# Starts its own roscore on a free port with main_sim.launch (Baxter stand-in without RViz, arm R
# on the simulated puppet, its arm controller, the simulated cameras, the keep-out zones of
# config/zones.yaml), then
# tools/screenshot_gui.py drives the real GUI like an operator and saves OUT_DIR/gui_main.png,
# OUT_DIR/gui_joint1.png and OUT_DIR/gui_camera_reach.jpg (default OUT_DIR: ./screenshots);
# with --feel, tools/screenshot_gui_feel.py instead puts the puppet in feel mode against the
# "patient body" zone and saves OUT_DIR/gui_feel.jpg.
# Stops everything it started. ROS_HOME is always a fresh temporary directory (its live
# arm_R.ini and the logs stay there); the exit status is non-zero when the scenario gives up.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCENARIO=screenshot_gui.py
if [ "${1:-}" = --feel ]; then
  SCENARIO=screenshot_gui_feel.py
  shift
fi
OUT_DIR="$(realpath -m "${1:-$ROOT/screenshots}")"
mkdir -p "$OUT_DIR"
# shellcheck disable=SC1091
. "$ROOT/tools/env.sh"
PORT="$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
export ROS_MASTER_URI="http://localhost:$PORT" LIBGL_ALWAYS_SOFTWARE=1 OUT_DIR PORT ROOT SCENARIO
# Always a fresh ROS_HOME: the scenario changes the config node's live arm_R.ini, which must never
# be the user's real one.
ROS_HOME="$(mktemp -d)"
export ROS_HOME ROS_LOG_DIR="$ROS_HOME/log"
exec xvfb-run -a -s "-screen 0 1600x900x24" bash -c '
  roslaunch -p "$PORT" robopuppet main_sim.launch rviz:=false gui:=false \
    zones_file:="$ROOT/catkin_ws/src/robopuppet/config/zones.yaml" \
    sim_link_prefix:="$ROS_HOME/robopuppet" >"$ROS_HOME/launch.log" 2>&1 &
  launch_pid=$!
  sleep 5
  status=0
  /usr/bin/python3 "$ROOT/tools/$SCENARIO" "$OUT_DIR" || status=$?
  kill -INT "$launch_pid"
  wait "$launch_pid" || true
  echo "logs: $ROS_HOME"
  exit $status'
