"""A ROS node or tool run as a process, or loaded as a nodelet (tests and tools that watch nodes come up)."""
import subprocess
import time

import rosgraph


def executable(package, name):
    """The command line ([path]) of `package`'s built executable `name`, found as rosrun finds it
    (catkin_find --libexec). Raises FileNotFoundError naming both when it is not built."""
    found = subprocess.run(["catkin_find", "--libexec", package, name], capture_output=True,
                           text=True).stdout.split()
    if not found:
        raise FileNotFoundError("%s is not built (catkin_find --libexec %s %s)" % (name, package, name))
    return [found[0]]


def advertised(node, master=None):
    """The topics the master lists `node` (a full name, '/my_node') as publishing, /rosout left
    out: every node advertises /rosout as it starts, ours advertise their own topics only once
    their parameters are read and valid."""
    master = master or rosgraph.Master('/mybot_common_node_process')
    publishers = master.getSystemState()[0]
    return sorted(t for t, nodes in publishers if node in nodes and t != '/rosout')


def subscribed(topics, master=None):
    """Whether every topic of `topics` (full names) has a subscriber: nodelets are loaded into
    their manager one by one, after it is up, and a command published before the last of them
    listens is lost."""
    master = master or rosgraph.Master('/mybot_common_node_process')
    subscribers = dict(master.getSystemState()[1])
    return all(subscribers.get(t) for t in topics)


def wait_until_advertising(proc, node, timeout=30.0, topics=()):
    """Waits until the process `proc` (a subprocess.Popen with its output piped), started as the
    node `node`, advertises a topic of its own, or every topic of `topics` (full names) when given:
    it is past its start-up and running. Returns the topics it advertises. A node registers its
    publishers one call to the master at a time, so a check for one topic passes `topics`: the
    first poll may see only another. Raises AssertionError with the process's output if it exits
    first or if `timeout` seconds of wall time pass (start-up is a wall-time matter: the node may
    not see sim time yet); the process is then killed. A check that a node "keeps running" for a
    fixed time passes without the node ever starting on a busy machine; this one does not."""
    master = rosgraph.Master('/mybot_common_node_process')
    deadline = time.monotonic() + timeout
    while True:
        advertising = advertised(node, master)
        if advertising and all(t in advertising for t in topics) and proc.poll() is None:
            return advertising
        if proc.poll() is not None:
            out = proc.communicate()[0]
            raise AssertionError('%s exited (%s) before it advertised %s:\n%s'
                                 % (node, proc.returncode, ', '.join(topics) or 'a topic', out))
        if time.monotonic() > deadline:
            proc.kill()
            out = proc.communicate()[0]
            raise AssertionError('%s advertised %s within %g s (it advertised %s):\n%s'
                                 % (node, ', '.join(topics) or 'no topic', timeout,
                                    ', '.join(advertising) or 'nothing', out))
        time.sleep(0.05)


def stop(proc, timeout=10.0):
    """Ends `proc` (SIGTERM, and SIGKILL if it still runs after `timeout` s) and returns its output."""
    proc.terminate()
    try:
        return proc.communicate(timeout=timeout)[0]
    except subprocess.TimeoutExpired:
        proc.kill()
        return proc.communicate()[0]
