#!/usr/bin/env bash
# Set up (install Debian packages, build) and run the simulated RoboPuppet system.
#   ./run.sh                         right puppet arm, simulated puppet and Baxter, RViz + GUI
#   ./run.sh run_side_L:=true        both arms (any main_sim.launch argument may follow)
# With no display (no $DISPLAY) it runs headless: rviz:=false gui:=false.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bash "$ROOT/tools/setup.sh"
. "$ROOT/tools/env.sh"
# Another RoboPuppet on the same ROS master would have its nodes replaced by ours (same names).
if /usr/bin/python3 - <<'PY'
import sys
import rosgraph
master = rosgraph.Master('/robopuppet_run_check')
try:
    nodes = {n for _, names in master.getSystemState()[0] for n in names} if master.is_online() else set()
except OSError:
    nodes = set()
sys.exit(0 if '/baxter_sim' in nodes else 1)
PY
then
  echo "[run] RoboPuppet already runs on the ROS master at ${ROS_MASTER_URI:-http://localhost:11311}." >&2
  echo "[run] Stop it first, or start this one on another master: ROS_MASTER_URI=http://localhost:11312 ./run.sh" >&2
  exit 1
fi
# The simulated puppets' pseudo-terminal links go to $ROS_HOME/robopuppet/, named after the
# ROS master (arm.launch's sim_link_prefix), so a second system on another master has its own.
args=("$@")
if [ -z "${DISPLAY:-}" ]; then
  echo "[run] no display (\$DISPLAY is empty): running headless, without RViz and the GUI."
  echo "[run] inspect it from another shell: . tools/env.sh; rostopic list"
  args=(rviz:=false gui:=false "${args[@]}")
fi
export LIBGL_ALWAYS_SOFTWARE="${LIBGL_ALWAYS_SOFTWARE:-1}"
exec roslaunch robopuppet main_sim.launch "${args[@]}"
