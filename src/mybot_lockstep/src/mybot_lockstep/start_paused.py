"""Starts a process whose node joins lockstep while simulated time stands.

A node started while time runs joins at a period that depends on load. Started through
start_paused, it joins at a fixed one: the caller's participant holds a period, the simulation is
paused from there, the process starts, and once the simulator names the node among the
participants of the tick it republishes while time stands, time moves on with the caller holding
the first period after the pause (its wake-up registered before the unpause, so that period
cannot pass unseen). A node that calls hold_next_period() as it starts (nav_timed) then begins in
the period after the pause, on every run.
"""
import subprocess
import threading
import time

import rospy
from std_srvs.srv import Empty

from mybot_lockstep.msg import Tick

__all__ = ['start_paused', 'unpause_when', 'finish']


def start_paused(ls, argv, node, timeout=60.0, **popen):
    """subprocess.Popen(argv, **popen), `node` (its resolved name) joining before time moves on.

    Under lockstep the caller's main thread must hold a period (it last slept through `ls`); it
    holds the first period after the pause when this returns. Raises RuntimeError, with the
    process killed, when the node has not joined within `timeout` s of wall time. Off lockstep:
    only starts the process."""
    if not ls.active:
        return subprocess.Popen(argv, **popen)
    joined = threading.Event()
    ticks = rospy.Subscriber('/lockstep/tick', Tick, lambda t: node in t.participants and joined.set(),
                             queue_size=10)
    try:
        rospy.ServiceProxy('/gazebo/pause_physics', Empty)()
        ls.release()  # start-up takes wall time; time stands meanwhile
        proc = subprocess.Popen(argv, **popen)
        deadline = time.monotonic() + timeout
        while not joined.is_set() and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.01)
        if not joined.is_set():
            proc.kill()
            rospy.ServiceProxy('/gazebo/unpause_physics', Empty)()
            raise RuntimeError('%s did not take part in lockstep within %.0f s of wall time (%s)' %
                               (node, timeout, 'it exited' if proc.poll() is not None else 'killed'))
        ls.hold_next_period(then=rospy.ServiceProxy('/gazebo/unpause_physics', Empty))
        return proc
    finally:
        ticks.unregister()


def unpause_when(ls, ready, what, timeout=60.0):
    """For a world launched paused: waits, in wall time as time stands, until ready() (the robots
    spawned, their controllers started), then unpauses with the caller holding the first period
    after it, so what it does next starts at the same period on every run. A caller that has
    not joined yet (defer_join, named in lockstep_wait_for) joins here. Raises RuntimeError
    naming `what` after `timeout` s."""
    deadline = time.monotonic() + timeout
    while not ready():
        if time.monotonic() > deadline:
            raise RuntimeError('%s: not within %.0f s of wall time' % (what, timeout))
        time.sleep(0.05)
    ls.hold_next_period(then=rospy.ServiceProxy('/gazebo/unpause_physics', Empty))


def finish(proc, timeout=60.0):
    """(returncode, output) of a process start_paused started, once it has exited (wall time: a
    node may linger after its last message); killed if it still runs after `timeout` s."""
    try:
        out = proc.communicate(timeout=timeout)[0]
    except subprocess.TimeoutExpired:
        proc.kill()
        out = proc.communicate()[0]
        out = (out or '') + '\n(killed: still running %.0f s after its test)' % timeout
    return proc.returncode, out or ''
