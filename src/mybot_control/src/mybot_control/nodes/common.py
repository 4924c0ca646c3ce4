"""Helpers shared by the rospy nodes."""
import sys

import rospy

from mybot_common import params


def get(name, default, check, **kwargs):
    """Read private parameter ~name and validate it with params.<check>."""
    full = "~" + name
    return check(full, rospy.get_param(full, default), **kwargs)


def run(node_name, main, **init_kwargs):
    """init_node, run main(); a ParamError ends the node with one message and exit code 2."""
    rospy.init_node(node_name, **init_kwargs)
    try:
        code = main()
    except params.ParamError as e:
        rospy.logfatal("%s: %s", rospy.get_name(), e)
        sys.exit(2)
    except rospy.ROSInterruptException:
        code = 0
    sys.exit(code or 0)
