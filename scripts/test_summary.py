#!/usr/bin/env python3
"""Counts test cases in the JUnit XML files under build/*/test_results.

rostest writes two files per test node: rosunit-*.xml with the node's own test
cases, and rostest-*.xml with one wrapper case that fails when the node crashed
or wrote no results. Cases are counted from every file except the passing
wrappers, so nothing is counted twice and a crashed node still counts as failed.
"""
import glob
import os
import sys
import xml.etree.ElementTree as ET


def why(element):
    """The failure's last informative line (the assertion), so a CI log says what broke."""
    text = (element.get("message") or "") + "\n" + (element.text or "")
    lines = [l.strip() for l in text.splitlines() if l.strip() and not l.strip().startswith("File ")]
    asserts = [l for l in lines if "Error" in l or "assert" in l.lower()]
    return (asserts[-1] if asserts else (lines[-1] if lines else "no message"))[:300]


def main(ws):
    passed, failed, skipped, failures = 0, 0, 0, []
    files = sorted(glob.glob(os.path.join(ws, "build", "*", "test_results", "**", "*.xml"), recursive=True))
    for path in files:
        pkg = os.path.relpath(path, os.path.join(ws, "build")).split(os.sep)[0]
        wrapper = os.path.basename(path).startswith("rostest-")
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as e:
            failed += 1
            failures.append("%s: unreadable result file %s (%s)" % (pkg, path, e))
            continue
        cases = root.iter("testcase")
        for case in cases:
            name = "%s: %s.%s" % (pkg, case.get("classname", ""), case.get("name", ""))
            bad = case.find("failure")
            if bad is None:
                bad = case.find("error")
            if bad is not None:
                failed += 1
                failures.append("%s  [%s]\n        %s" % (name, os.path.basename(path), why(bad)))
            elif case.find("skipped") is not None:
                skipped += 1
            elif not wrapper:
                passed += 1
        # A results file with failures but no test cases (e.g. catkin's MISSING-*.xml).
        if root.find(".//testcase") is None and int(root.get("failures", 0)) + int(root.get("errors", 0)) > 0:
            failed += 1
            failures.append("%s: %s" % (pkg, os.path.basename(path)))
    for f in failures:
        print("FAILED  " + f)
    if skipped:
        print("%d skipped" % skipped)
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else os.getcwd()))
