# Source this in an interactive shell to use the workspace by hand:
#   source scripts/env.sh
# (puts .venv/bin with xacro first on PATH and sources devel/setup.bash)
_mybot_ws="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="$_mybot_ws/.venv/bin:$PATH"
[ -f "$_mybot_ws/devel/setup.bash" ] && source "$_mybot_ws/devel/setup.bash"
unset _mybot_ws
