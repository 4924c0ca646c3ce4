# Shared by scripts/setup, demo, test, bench: workspace paths and environment.
# Sourced, not run.
WS="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$WS/.venv"

log() { printf '[%s] %s\n' "$(basename "$0")" "$*"; }
die() { printf '[%s] ERROR: %s\n' "$(basename "$0")" "$*" >&2; exit 1; }

# catkin build's parallelism: one package at a time (-p 1), two compile jobs in it (-j 2). Two
# packages configuring at once in the merged devel space can run devel/_setup_util.py while the
# other rewrites it: Debian 12's catkin 0.8.10 copies it in place (fixed upstream by ros/catkin#1150,
# copy then rename). A clean clone's build failed that way once on 2026-11-29 ("can't open file
# devel/_setup_util.py", then a SyntaxError in generate_cached_setup.py).
CATKIN_JOBS=(-j2 -p1)

# Put the venv (Debian's python3 + xacro) first so a pyenv/conda python3 on
# PATH never shadows rospy, then overlay the built workspace.
ws_env() {
  export PATH="$VENV/bin:$PATH"
  export PYTHONDONTWRITEBYTECODE=1
  if [ -f "$WS/devel/setup.bash" ]; then
    # shellcheck disable=SC1091
    set +u; source "$WS/devel/setup.bash"; set -u
  fi
  export ROS_HOME="${ROS_HOME:-$WS/.ros}"
}
