#!/usr/bin/env bash
# Set up (install Debian packages, build) and run the simulated RoboPuppet system.
#   ./run.sh                         right puppet arm, simulated puppet and Baxter, RViz + GUI
#   ./run.sh run_side_L:=true        both arms (any main_sim.launch argument may follow)
# With no display (no $DISPLAY) it runs headless: rviz:=false gui:=false.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bash "$ROOT/tools/setup.sh"
. "$ROOT/tools/env.sh"
args=("$@")
if [ -z "${DISPLAY:-}" ]; then
  echo "[run] no display (\$DISPLAY is empty): running headless, without RViz and the GUI."
  echo "[run] inspect it from another shell: . tools/env.sh; rostopic list"
  args=(rviz:=false gui:=false "${args[@]}")
fi
export LIBGL_ALWAYS_SOFTWARE="${LIBGL_ALWAYS_SOFTWARE:-1}"
exec roslaunch robopuppet main_sim.launch "${args[@]}"
