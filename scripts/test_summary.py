#!/usr/bin/env python3
"""Per-suite summary of the JUnit XML results of ./railvib test.

usage: test_summary.py [--failed-log CTEST_LastTestsFailed.log]... [--expect NAME,NAME...] DIR...

Reads every result file under the DIRs (gtest, rostest, scripts). Exits non-zero
if any test case failed or errored, if no test case ran, or if an expected
suite left no result file (a test binary that was not built, not registered or
did not start passes nothing, so a missing suite fails the run). The expected
suites are EXPECTED_SUITES (the normal build) unless --expect names them; a
name is a result file's stem (e.g. gtest-soil, rostest-haren, san-gtest-soil).
Ends with the plain line 'railvib: N passed, N failed'.
"""
import argparse
import pathlib
import sys
import xml.etree.ElementTree as ET

# One result file per suite of the normal build (CMakeLists.txt registers each).
UNIT_DOMAINS = ["common", "io", "signal", "track", "vehicle", "soil", "building", "coupling", "validation",
                "scenario"]
EXPECTED_SUITES = ([f"gtest-{d}" for d in UNIT_DOMAINS]
                   + ["gtest-soil_mpi", "rostest-track", "rostest-haren", "scenario-checks", "netns-hosts", "node-fuzz",
                      "robustness-cases", "tool-commands", "script-tests", "export-tests", "monitor-tests", "property-tests"])
# The sanitizer build (./railvib sanitize): the unit tests and the node-level fuzz.
# (test_coupling's Craig-Bampton reductions are left out: minutes under the sanitizers; the
# soil and building tests it builds on are in.)
SANITIZER_SUITES = [f"san-gtest-{d}" for d in UNIT_DOMAINS if d not in ("coupling", "validation")] + ["san-node-fuzz"]


def summarize(dirs, failed_logs, expected):
    """(rows, passed, failed, skipped): one row per suite, plus one per missing or CTest-failed suite."""
    rows = []
    total_pass = total_fail = total_skip = 0
    seen = set()
    for root in dirs:
        # rosunit-*.xml repeat, case by case, what rostest-*.xml reports per <test>: count the latter only.
        for f in sorted(p for p in pathlib.Path(root).rglob("*.xml") if not p.name.startswith("rosunit-")):
            seen.add(f.stem)
            try:
                tree = ET.parse(f)
            except ET.ParseError as e:
                rows.append((f.stem, 0, 1, 0, f"unreadable result file: {e}"))
                total_fail += 1
                continue
            suites = [tree.getroot()] if tree.getroot().tag == "testsuite" else list(tree.getroot().iter("testsuite"))
            cases_in_file = 0
            for suite in suites:
                cases = suite.findall("testcase")
                if not cases:
                    continue
                cases_in_file += len(cases)
                fail = sum(1 for c in cases if c.find("failure") is not None or c.find("error") is not None)
                skip = sum(1 for c in cases if c.find("skipped") is not None or c.get("status") == "notrun")
                passed = len(cases) - fail - skip
                rows.append((f"{f.stem}:{suite.get('name')}", passed, fail, skip, ""))
                total_pass += passed
                total_fail += fail
                total_skip += skip
            if cases_in_file == 0:
                rows.append((f.stem, 0, 1, 0, "no test case in the result file"))
                total_fail += 1
    for name in expected:
        if name not in seen:
            rows.append((name, 0, 1, 0, "expected suite left no result (not built, not registered, or did not run)"))
            total_fail += 1
    # A test binary that crashed or timed out leaves no failing XML: take CTest's word too.
    for log in failed_logs:
        failed_log = pathlib.Path(log)
        if failed_log.exists():
            for line in failed_log.read_text().splitlines():
                name = line.split(":", 1)[-1].strip()
                if name:
                    rows.append((f"ctest:{name}", 0, 1, 0, "CTest reports this test failed (crash, timeout or failures)"))
                    total_fail += 1
    return rows, total_pass, total_fail, total_skip


def main(argv):
    parser = argparse.ArgumentParser(description="per-suite summary of railvib test results")
    parser.add_argument("dirs", nargs="+")
    parser.add_argument("--failed-log", action="append", default=[])
    parser.add_argument("--expect", help="comma-separated result file stems that must be there")
    options = parser.parse_args(argv[1:])
    expected = EXPECTED_SUITES if options.expect is None else [n for n in options.expect.split(",") if n]
    rows, total_pass, total_fail, total_skip = summarize(options.dirs, options.failed_log, expected)
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
    sys.exit(main(sys.argv))
