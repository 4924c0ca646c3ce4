#!/usr/bin/env bash
# env-loader for roslaunch <machine> tags (runs on the machine the nodes start on):
#   <machine name="gopigo" address="gopigo.local" user="pi"
#            env-loader="/home/pi/mybot_ws/src/gopigo_bringup/scripts/gopigo_env.sh"/>
# It sources the workspace next to it, then ~/.gopigo_env (put ROS_IP=... there if
# the machine has several addresses), picks ROS_IP from the first address if still
# unset, and runs the command roslaunch passes.
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
for setup in "${GOPIGO_WS:+$GOPIGO_WS/devel/setup.bash}" \
             "$here/../../../devel/setup.bash" \
             "$here/../../../setup.bash"; do
  if [ -n "$setup" ] && [ -f "$setup" ]; then
    # shellcheck disable=SC1090
    source "$setup"
    break
  fi
done
if [ -z "${ROS_DISTRO:-}${ROS_PACKAGE_PATH:-}" ]; then
  echo "gopigo_env.sh: no workspace setup.bash found near $here (set GOPIGO_WS)" >&2
  exit 1
fi
# shellcheck disable=SC1090
[ -f "$HOME/.gopigo_env" ] && source "$HOME/.gopigo_env"
if [ -z "${ROS_IP:-}" ] && [ -z "${ROS_HOSTNAME:-}" ]; then
  ROS_IP="$(hostname -I 2>/dev/null | awk '{print $1}')"
  [ -n "$ROS_IP" ] && export ROS_IP
fi
exec "$@"
