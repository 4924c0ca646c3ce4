#!/usr/bin/env python3
"""Runs every package's ctest tests (gtest, rostest, pytest), JOBS at a time.

    run_suites.py WS JOBS PKG...

Why in parallel: the simulated tests run in lockstep, so a test's result does not depend
on how busy the machine is (the gate passes beside a one-core busy loop); a second test
beside it is such a load. Each rostest starts its own master on a free port, and a test's
temporary files are its own, so two tests never share state.

Order: longest first, from the last run's times in WS/.test-times, on a first run from those of
a clean run kept in WS/scripts/test_times.txt (refresh it from .test-times when tests change
much), so the longest test never starts last.

Each test's whole output goes to WS/.catkin-test.log in one piece when it finishes, with
one progress line on stdout: package, test, result, seconds, CPU seconds. WS/.test-times gets
"seconds package test cpu-seconds" per test for the slowest-ten list and the next run's order.
"""
import os
import re
import subprocess
import sys
import threading
import time

LISTED = re.compile(r"^\s*Test\s+#(\d+):\s+(\S+)\s*$")
RESULT = re.compile(r"Test\s+#\d+:\s+(\S+)\s+\.*[\s*]*(Passed|\*\*\*Failed|Failed|\*\*\*Timeout|"
                    r"\*\*\*Exception|Not Run)[^0-9]*([0-9.]+)\s+sec")


def list_tests(ws, pkg):
    """(number, ctest name) of one package's tests, in ctest's order."""
    build = os.path.join(ws, "build", pkg)
    if not os.path.isdir(build):
        return []
    out = subprocess.run(["ctest", "-N"], cwd=build, capture_output=True, text=True).stdout
    return [(int(m.group(1)), m.group(2)) for m in map(LISTED.match, out.splitlines()) if m]


def short_name(pkg, ctest_name):
    return ctest_name[len("_ctest_%s_" % pkg):] if ctest_name.startswith("_ctest_%s_" % pkg) else ctest_name


def previous_times(path):
    times = {}
    try:
        with open(path) as f:
            for line in f:
                if line.startswith("#") or not line.strip():
                    continue
                sec, pkg, name = line.split()[:3]
                times[(pkg, name)] = float(sec)
    except (OSError, ValueError):
        return {}
    return times


def main(ws, jobs, pkgs):
    times_path = os.path.join(ws, ".test-times")
    log_path = os.path.join(ws, ".catkin-test.log")
    # A fresh clone (CI's every run) has no times of its own: it takes those of a clean run
    # recorded in the repository. Without them, a 63 s gtest that ran last left one core idle
    # for most of its run (the suites 601 s where the tests' CPU was 1063 s, 2026-11-29).
    last = previous_times(times_path) or previous_times(os.path.join(ws, "scripts", "test_times.txt"))
    tests = [(pkg, number, name) for pkg in pkgs for number, name in list_tests(ws, pkg)]

    def cost(test):
        pkg, _, name = test
        known = last.get((pkg, short_name(pkg, name)))
        if known is None:  # a test new since those times: a rostest takes about 15 s
            known = 15.0 if "rostest" in name else 2.0
        return -known  # longest first: the last to start are the shortest

    queue = sorted(tests, key=cost)
    lock = threading.Lock()
    done = []
    with open(log_path, "w") as log, open(times_path + ".new", "w") as times:

        def worker():
            while True:
                with lock:
                    if not queue:
                        return
                    pkg, number, name = queue.pop(0)
                start = time.monotonic()
                proc = subprocess.Popen(["ctest", "--output-on-failure", "-I", "%d,%d" % (number, number)],
                                        cwd=os.path.join(ws, "build", pkg), stdout=subprocess.PIPE,
                                        stderr=subprocess.STDOUT, text=True)
                stdout = proc.stdout.read()
                # wait4, not wait: the CPU time of the whole test (ctest, rostest and every node
                # it started and reaped), which tells a test that computes from one that waits.
                _, status, usage = os.wait4(proc.pid, 0)
                proc.returncode = os.waitstatus_to_exitcode(status)
                cpu = usage.ru_utime + usage.ru_stime
                m = RESULT.search(stdout)
                sec = float(m.group(3)) if m else time.monotonic() - start
                ok = bool(m) and m.group(2) == "Passed" and proc.returncode == 0
                with lock:
                    done.append(ok)
                    log.write("==== %s %s\n%s\n" % (pkg, name, stdout))
                    log.flush()
                    times.write("%.1f %s %s %.1f\n" % (sec, pkg, short_name(pkg, name), cpu))
                    times.flush()
                    print("[test] %-20s %-62s %-6s %7.1f s  cpu %6.1f s  (%d/%d)" % (
                        pkg, short_name(pkg, name), "ok" if ok else "FAILED", sec, cpu, len(done), len(tests)),
                          flush=True)

        threads = [threading.Thread(target=worker) for _ in range(max(1, jobs))]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    os.replace(times_path + ".new", times_path)
    return 0 if all(done) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], int(sys.argv[2]), sys.argv[3:]))
