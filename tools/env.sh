# Source this file to use the built workspace by hand: . tools/env.sh
# (the same as sourcing catkin_ws/devel/setup.bash, with Debian's python3 first on PATH).
_rp_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="/usr/bin:/bin:$PATH"
# catkin's setup scripts read unset variables: let them, even under 'set -u'.
case $- in *u*) _rp_nounset=1; set +u ;; *) _rp_nounset= ;; esac
# shellcheck disable=SC1091
. "$_rp_root/catkin_ws/devel/setup.bash"
[ -n "$_rp_nounset" ] && set -u
unset _rp_root _rp_nounset
