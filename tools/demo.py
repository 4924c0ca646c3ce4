#!/usr/bin/env python3
"""The main job, headless: runs each stage against its own private ROS master
and prints progress lines as it goes; exits 0 only if every stage succeeded."""
import argparse
import os
import socket
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

ROBOTS = ("mybot", "swerve", "gopigo")


def log(msg):
    print("[demo] " + msg, flush=True)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Roslaunch:
    """roslaunch with its own roscore on a free port, stopped on exit."""

    def __init__(self, pkg, launch_file, *args, logdir):
        self.port = free_port()
        self.env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:%d" % self.port, ROS_IP="127.0.0.1")
        self.env.pop("ROS_HOSTNAME", None)
        os.makedirs(logdir, exist_ok=True)
        self.logfile = open(os.path.join(logdir, "%s_%d.log" % (os.path.splitext(launch_file)[0], self.port)), "w")
        self.proc = subprocess.Popen(["roslaunch", "-p", str(self.port), pkg, launch_file] + list(args),
                                     env=self.env, stdout=self.logfile, stderr=subprocess.STDOUT)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.proc.terminate()
        try:
            self.proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        self.logfile.close()


def robot_frames(model, out_dir, timeout):
    """Expands a robot, publishes its tf tree headless and returns its frames."""
    with Roslaunch("mybot_description", "display.launch", "model:=" + model, "rviz:=false",
                   logdir=os.path.join(out_dir, "logs")) as rl:
        probe = subprocess.run([sys.executable, "-c", TF_PROBE, str(timeout)], env=rl.env,
                               capture_output=True, text=True, timeout=timeout + 30)
        if probe.returncode != 0:
            raise RuntimeError("%s: %s" % (model, probe.stderr.strip().splitlines()[-1:] or "tf probe failed"))
        return probe.stdout.strip().splitlines()


# Runs in a child process so each robot gets a fresh rospy node on its own master.
TF_PROBE = r'''
import sys, time, xml.etree.ElementTree as ET
import rospy, tf2_ros
timeout = float(sys.argv[1])
deadline = time.monotonic() + timeout
while True:
    try:
        rospy.get_master().getPid()
        if rospy.has_param("robot_description"):
            break
    except Exception:
        pass
    if time.monotonic() > deadline:
        sys.exit("no robot_description on the master")
    time.sleep(0.1)
rospy.init_node("demo_tf_probe", disable_signals=True)
links = [l.get("name") for l in ET.fromstring(rospy.get_param("robot_description")).findall("link")]
buf = tf2_ros.Buffer(); tf2_ros.TransformListener(buf)
while time.monotonic() < deadline:
    missing = [l for l in links if not buf.can_transform("base_footprint", l, rospy.Time(0))]
    if not missing:
        for l in links:
            t = buf.lookup_transform("base_footprint", l, rospy.Time(0)).transform.translation
            print("%-24s %7.3f %7.3f %7.3f" % (l, t.x, t.y, t.z))
        sys.exit(0)
    time.sleep(0.1)
sys.exit("frames not in tf: %s" % missing)
'''


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--robot", choices=ROBOTS + ("all",), default="all", help="robot(s) to run (default: all)")
    ap.add_argument("--output", default=os.path.join(os.getcwd(), "output", time.strftime("demo-%Y%m%d-%H%M%S")),
                    help="output folder for the report, pictures and logs")
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds allowed per stage")
    args = ap.parse_args()
    os.makedirs(args.output, exist_ok=True)
    robots = ROBOTS if args.robot == "all" else (args.robot,)
    ok = True
    report = []
    t0 = time.monotonic()
    for model in robots:
        log("%s: expanding the xacro and publishing its tf tree headless" % model)
        try:
            frames = robot_frames(model, args.output, args.timeout)
        except Exception as e:  # a stage failure is reported, the others still run
            log("%s: FAILED: %s" % (model, e))
            ok = False
            report.append("%s: FAILED (%s)" % (model, e))
            continue
        log("%s: %d frames reachable from base_footprint (x y z in m):" % (model, len(frames)))
        for f in frames:
            print("    " + f)
        report.append("%s: %d frames OK" % (model, len(frames)))
    report.append("wall time: %.1f s" % (time.monotonic() - t0))
    with open(os.path.join(args.output, "report.txt"), "w") as f:
        f.write("\n".join(report) + "\n")
    log("report: %s" % os.path.join(args.output, "report.txt"))
    log("mission %s" % ("succeeded" if ok else "FAILED"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
