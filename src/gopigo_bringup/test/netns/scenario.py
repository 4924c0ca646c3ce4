#!/usr/bin/env python3
"""Two machines for real: a "host" and a "pi" network namespace joined by a veth pair.

Run as root from the test (test/python/test_two_machines.py) with the workspace
environment sourced:  scenario.py <host-ns> <pi-ns> <host-veth> <host-ip> <pi-ip>
This process runs inside the host namespace: it starts the ROS master there and
acts as the host-side controller (publishes the wheel commands the wheel
controller would and watches joint_states); the driver runs in the pi namespace
with ROS_MASTER_URI/ROS_IP pointing across the link. Steps:
  1. a command on the host moves the simulated motors on the pi;
  2. `ip link set <host-veth> down`: the pi's driver stops the motors within 0.6 s;
  3. `ip link set <host-veth> up`: control resumes.
Exit 0 when every check passes; a message per failure otherwise.
"""
import os
import re
import signal
import subprocess
import sys
import tempfile
import time

PORT = 11311


def log(msg):
    print("[scenario %7.2f] %s" % (time.monotonic() - T0, msg), flush=True)


T0 = time.monotonic()


def start(cmd, env, logfile, netns=None):
    if netns:
        cmd = ["ip", "netns", "exec", netns] + cmd
    out = open(logfile, "w")
    return subprocess.Popen(cmd, env=env, stdout=out, stderr=subprocess.STDOUT, start_new_session=True)


def stop(proc):
    if proc is None or proc.poll() is not None:
        return
    os.killpg(proc.pid, signal.SIGINT)
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()


def wait_for(pred, timeout, what):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if pred():
            return True
        time.sleep(0.02)
    log("timed out after %.1f s waiting for %s" % (timeout, what))
    return False


def main():
    host_ns, pi_ns, host_veth, host_ip, pi_ip = sys.argv[1:6]
    tmp = tempfile.mkdtemp(prefix="gopigo_netns_")
    base = dict(os.environ, ROS_LOG_DIR=tmp, ROS_HOME=tmp, PYTHONUNBUFFERED="1")
    base.pop("ROS_HOSTNAME", None)
    master = "http://%s:%d" % (host_ip, PORT)
    host_env = dict(base, ROS_MASTER_URI=master, ROS_IP=host_ip)
    pi_env = dict(base, ROS_MASTER_URI=master, ROS_IP=pi_ip)
    failures = []
    core = driver = None
    try:
        core = start(["roscore", "-p", str(PORT)], host_env, os.path.join(tmp, "roscore.log"))
        os.environ.update(host_env)
        import rosgraph
        if not wait_for(lambda: rosgraph.is_master_online(master), 30, "the master"):
            return 1
        driver_log = os.path.join(tmp, "driver.log")
        driver = start(["rosrun", "gopigo_bringup", "gopigo_driver", "_gopigo_on:=false",
                        "_cmd_timeout:=0.5", "_rate:=20"], pi_env, driver_log, netns=pi_ns)

        import rospy
        from sensor_msgs.msg import JointState
        from std_msgs.msg import Float32
        rospy.init_node("host_controller", disable_signals=True)
        states = []  # (receive wall time, stamp, positions, velocities)
        rospy.Subscriber("joint_states", JointState,
                         lambda m: states.append((time.time(), m.header.stamp.to_sec(),
                                                  tuple(m.position), tuple(m.velocity))))
        lpub = rospy.Publisher("lwheel_angular_vel_motor", Float32, queue_size=1)
        rpub = rospy.Publisher("rwheel_angular_vel_motor", Float32, queue_size=1)
        command = [0.0]

        def send(_event):
            lpub.publish(Float32(command[0]))
            rpub.publish(Float32(command[0]))
        rospy.Timer(rospy.Duration(0.05), send)

        if not wait_for(lambda: len(states) > 5, 30, "joint_states from the pi"):
            failures.append("no joint_states from the driver in the pi namespace")
            return 1
        log("driver on the pi is publishing; commanding 3 rad/s")
        command[0] = 3.0
        moving = lambda: states and min(states[-1][3]) > 2.5
        if not wait_for(moving, 10, "wheels at 3 rad/s"):
            failures.append("a command from the host did not move the simulated motors on the pi")
            return 1
        log("wheels turning: %s rad/s" % (states[-1][3],))
        time.sleep(1.0)

        log("cutting the link: ip link set %s down" % host_veth)
        t_cut = time.time()
        subprocess.check_call(["ip", "link", "set", host_veth, "down"])
        time.sleep(2.5)
        t_restore = time.time()
        subprocess.check_call(["ip", "link", "set", host_veth, "up"])
        log("link restored after %.2f s" % (t_restore - t_cut))

        # The driver logs the stop with its own (ROS = wall) clock.
        def stop_time():
            with open(driver_log) as f:
                for line in f:
                    m = re.search(r"\[(\d+\.\d+)\]: motors stopped: (.*)", line)
                    if m and float(m.group(1)) > t_cut:
                        return float(m.group(1)), m.group(2)
            return None
        if not wait_for(lambda: stop_time() is not None, 5, "the driver's stop line"):
            failures.append("the driver never stopped the motors after the link was cut")
        else:
            t_stop, reason = stop_time()
            log("driver stopped the motors %.3f s after the cut (%s)" % (t_stop - t_cut, reason.strip()))
            if t_stop - t_cut > 0.6:
                failures.append("motors stopped %.3f s after the cut (> 0.6 s)" % (t_stop - t_cut))

        # Control resumes: fresh joint_states (stamped after the restore) show the wheels turning.
        resumed = lambda: any(s[1] > t_restore and min(s[3]) > 2.5 for s in states[-5:])
        if not wait_for(resumed, 20, "control to resume after the restore"):
            failures.append("control did not resume after the link came back")
        else:
            log("control resumed %.2f s after the restore" % (
                next(s[1] for s in states if s[1] > t_restore and min(s[3]) > 2.5) - t_restore))
        # Samples the pi buffered during the outage: the wheels stood still once stopped.
        outage = [s for s in states if t_cut + 1.0 < s[1] < t_restore - 0.1]
        if outage:
            spread = max(max(s[2][i] for s in outage) - min(s[2][i] for s in outage) for i in (0, 1))
            log("%d joint_states from the outage reached the host; wheel travel in them: %.4f rad"
                % (len(outage), spread))
            if spread > 0.02:
                failures.append("wheels kept turning during the outage (%.3f rad)" % spread)

        command[0] = 0.0
        time.sleep(0.3)
    finally:
        for f in failures:
            log("FAIL: " + f)
        stop(driver)
        stop(core)
        if failures or os.environ.get("GOPIGO_NETNS_VERBOSE"):
            for name in ("driver.log",):
                p = os.path.join(tmp, name)
                if os.path.exists(p):
                    log("---- %s ----\n%s" % (name, open(p).read()[-4000:]))
    if failures:
        return 1
    log("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
