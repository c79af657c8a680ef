#!/usr/bin/env python3
"""Counts JUnit test results under the given folders, lists each failure, prints 'N passed, N failed'.

Extra checks run by the test script are passed as NAME=STATUS (STATUS 0 = passed) and count as one test each.
"""
import glob
import os
import sys
import xml.etree.ElementTree as ET


def cases(path):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as err:
        yield os.path.basename(path), f"unreadable result file: {err}"
        return
    found = False
    for case in root.iter("testcase"):
        found = True
        name = f"{case.get('classname', '')}.{case.get('name', '')}"
        bad = case.find("failure")
        if bad is None:
            bad = case.find("error")
        if case.find("skipped") is not None:
            continue
        yield name, None if bad is None else (bad.get("message") or bad.text or "failed")[:300]
    if not found:
        # A result file without test cases is a test binary that ran nothing: a failure, not a pass.
        yield os.path.basename(path), "result file holds no test case"


def main(argv):
    passed, failed = 0, 0
    for arg in argv:
        if "=" in arg and not os.path.isdir(arg):
            name, status = arg.split("=", 1)
            if status == "0":
                passed += 1
            else:
                failed += 1
                print(f"FAILED  {name} (exit {status})")
            continue
        for path in sorted(glob.glob(os.path.join(arg, "**", "*.xml"), recursive=True)):
            for name, err in cases(path):
                if err is None:
                    passed += 1
                else:
                    failed += 1
                    print(f"FAILED  {name}: {err.strip().splitlines()[0] if err.strip() else err}")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
