#!/usr/bin/env python3
"""Per-suite summary of the gtest and rostest JUnit XML results of ./railvib test.

Usage: test_summary.py RESULTS_DIR [CTEST_LastTestsFailed.log]

Exits non-zero if any test case failed or errored, or if no test case ran.
Ends with the plain line 'railvib: N passed, N failed'.
"""
import pathlib
import sys
import xml.etree.ElementTree as ET


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    # rosunit-*.xml repeat, case by case, what rostest-*.xml reports per <test>: count the latter only.
    files = sorted(f for f in root.rglob("*.xml") if not f.name.startswith("rosunit-"))
    total_pass = total_fail = total_skip = 0
    rows = []
    for f in files:
        try:
            tree = ET.parse(f)
        except ET.ParseError as e:
            rows.append((f.stem, 0, 1, 0, f"unreadable result file: {e}"))
            total_fail += 1
            continue
        for suite in tree.getroot().iter("testsuite"):
            cases = suite.findall("testcase")
            if not cases:
                continue
            fail = sum(1 for c in cases if c.find("failure") is not None or c.find("error") is not None)
            skip = sum(1 for c in cases if c.find("skipped") is not None or c.get("status") == "notrun")
            passed = len(cases) - fail - skip
            rows.append((f"{f.stem}:{suite.get('name')}", passed, fail, skip, ""))
            total_pass += passed
            total_fail += fail
            total_skip += skip
    # A test binary that crashed or timed out leaves no failing XML: take CTest's word too.
    if len(sys.argv) > 2:
        failed_log = pathlib.Path(sys.argv[2])
        if failed_log.exists():
            for line in failed_log.read_text().splitlines():
                name = line.split(":", 1)[-1].strip()
                if name:
                    rows.append((f"ctest:{name}", 0, 1, 0, "CTest reports this test failed (crash, timeout or failures)"))
                    total_fail += 1
    width = max([len(r[0]) for r in rows] + [10])
    print("\nper-suite summary:")
    for name, p, fl, s, note in rows:
        flag = "FAIL" if fl else "ok"
        print(f"  {name:<{width}}  {p:4d} passed {fl:3d} failed {s:3d} skipped  {flag} {note}")
    if total_pass + total_fail == 0:
        print("railvib: no test ran")
        print("0 passed, 1 failed")
        return 1
    print(f"railvib: {total_pass} passed, {total_fail} failed" + (f", {total_skip} skipped" if total_skip else ""))
    return 1 if total_fail else 0


if __name__ == "__main__":
    sys.exit(main())
