#!/usr/bin/env python3
"""Summarise the JUnit XML that `catkin_make run_tests` leaves in a results folder.

Counts every <testcase> of the gtest binaries (gtest-*.xml) and of the tests inside rostests
(rosunit-*.xml). A rostest wrapper (rostest-*.xml) holds one case that passes when its test process ran to
the end; it is counted only when it failed (crash, time-limit, no results), so no test is counted twice.
Prints the failed cases with the start of their messages and, last, the line "N passed, N failed[, N skipped]". Exit 1 on any failure or
when nothing ran.
"""
import glob
import os
import sys
import xml.etree.ElementTree as ElementTree


def _first_lines(text, count=6):
    """The start of a failure's message: enough to see which assertion, without a page of output."""
    lines = text.strip().splitlines()
    return "\n    ".join(lines[:count]) + ("\n    ..." if len(lines) > count else "")


def cases(path):
    root = ElementTree.parse(path).getroot()
    for case in root.iter("testcase"):
        name = "%s.%s" % (case.get("classname", ""), case.get("name", ""))
        problem = case.find("failure")
        if problem is None:
            problem = case.find("error")
        if problem is not None:
            yield name, "failed", _first_lines(problem.get("message") or problem.text or "")
        elif case.find("skipped") is not None or case.get("status") == "notrun":
            yield name, "skipped", ""
        else:
            yield name, "passed", ""


def main(folder):
    counts = {"passed": 0, "failed": 0, "skipped": 0}
    failed = []
    files = sorted(glob.glob(os.path.join(folder, "**", "*.xml"), recursive=True))
    for path in files:
        wrapper = os.path.basename(path).startswith("rostest-")
        try:
            results = list(cases(path))
        except ElementTree.ParseError as error:
            results = [(os.path.basename(path), "failed", "unreadable")]
            print("unreadable result file %s: %s" % (path, error))
        for name, outcome, message in results:
            if wrapper and outcome == "passed":
                continue
            counts[outcome] += 1
            if outcome == "failed":
                failed.append("%s (%s)%s" % (name, os.path.basename(path), "\n    " + message if message else ""))
    for name in failed:
        print("FAILED: " + name)
    line = "%d passed, %d failed" % (counts["passed"], counts["failed"])
    if counts["skipped"]:
        line += ", %d skipped" % counts["skipped"]
    if counts["passed"] + counts["failed"] == 0:
        print("no test results found in " + folder)
    print(line)
    return 0 if counts["failed"] == 0 and counts["passed"] > 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "ws/build/test_results"))
