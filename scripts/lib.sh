# Shared by scripts/setup, demo, test, bench: workspace paths and environment.
# Sourced, not run.
WS="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$WS/.venv"

log() { printf '[%s] %s\n' "$(basename "$0")" "$*"; }
die() { printf '[%s] ERROR: %s\n' "$(basename "$0")" "$*" >&2; exit 1; }

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
