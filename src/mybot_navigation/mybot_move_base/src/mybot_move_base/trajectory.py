"""Ground-truth trajectory measures shared by the navigation tests and the demo."""
import numpy as np


def sideways_distance(poses):
    """(metres moved along the body's y axis, metres moved in all) over a trajectory of
    (t, x, y, yaw) rows. Each step is projected on the body axes at its mid heading, so a
    diff-drive robot turning while it drives moves ~0 m sideways; a holonomic one strafing does not."""
    p = np.asarray(poses, float).reshape(-1, 4)
    if len(p) < 2:
        return 0.0, 0.0
    d = np.diff(p[:, 1:3], axis=0)
    dyaw = np.diff(p[:, 3])
    yaw = p[:-1, 3] + 0.5 * np.arctan2(np.sin(dyaw), np.cos(dyaw))
    lateral = -np.sin(yaw) * d[:, 0] + np.cos(yaw) * d[:, 1]
    return float(np.abs(lateral).sum()), float(np.hypot(d[:, 0], d[:, 1]).sum())
