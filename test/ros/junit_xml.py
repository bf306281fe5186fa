"""JUnit XML of a unittest run (what scripts/test_summary.py and CTest's result folder read)."""
import pathlib
import re
import time
import unittest
import xml.etree.ElementTree as ET


# ROS logs colour their lines with ANSI escapes; XML 1.0 allows no control character but tab, newline and
# carriage return, and ElementTree writes them as they are, leaving a file no parser reads.
_ANSI_ESCAPE = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")
_XML_FORBIDDEN = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")


def xml_text(text):
    """text as an XML 1.0 document can hold it: colour escapes dropped, other control characters shown as
    \\xNN (a failure's log stays readable, the result file parseable)."""
    text = _ANSI_ESCAPE.sub("", text)
    return _XML_FORBIDDEN.sub(lambda m: f"\\x{ord(m.group()):02x}", text)


class TimedTextTestResult(unittest.TextTestResult):
    """A verbose result that also keeps each test's wall time (seconds by test id), written as the JUnit
    time of its case: where a suite's time goes."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.seconds = {}
        self._started = {}

    def startTest(self, test):
        self._started[test.id()] = time.monotonic()
        super().startTest(test)

    def stopTest(self, test):
        super().stopTest(test)
        if test.id() in self._started:
            self.seconds[test.id()] = time.monotonic() - self._started.pop(test.id())


def run_verbose(suite):
    """The suite run as unittest's verbose runner runs it, each test timed."""
    return unittest.TextTestRunner(verbosity=2, resultclass=TimedTextTestResult).run(suite)


def write_junit(result, suite_name, case_class, path):
    """One <testcase> per test of case_class (a TestCase class, or a sequence of them), with its failure or
    error text."""
    classes = case_class if isinstance(case_class, (list, tuple)) else (case_class,)
    suite = ET.Element("testsuite", name=suite_name, tests=str(result.testsRun),
                       failures=str(len(result.failures)), errors=str(len(result.errors)))
    failed = {t.id(): msg for t, msg in result.failures}
    errored = {t.id(): msg for t, msg in result.errors}
    ids = set()
    for cls in classes:
        tests = list(unittest.defaultTestLoader.loadTestsFromTestCase(cls))
        ids.update(test.id() for test in tests)
        # A failed setUpClass is reported under an id of its own ("setUpClass (module.Class)"): the checks
        # it kept from running did not pass.
        setup_failed = any(cls.__name__ in i and i not in {t.id() for t in tests} for i in errored)
        for test in tests:
            case = ET.SubElement(suite, "testcase", classname=cls.__name__, name=test.id().split(".")[-1],
                                 time=f"{getattr(result, 'seconds', {}).get(test.id(), 0.0):.3f}")
            if test.id() in failed:
                ET.SubElement(case, "failure", message="failed").text = xml_text(failed[test.id()])
            if test.id() in errored:
                ET.SubElement(case, "error", message="error").text = xml_text(errored[test.id()])
            elif setup_failed and test.id() not in failed:
                ET.SubElement(case, "error", message="not run: the class's setUpClass failed")
    for test_id, msg in errored.items():
        if test_id not in ids:
            case = ET.SubElement(suite, "testcase", classname="setup", name=test_id)
            ET.SubElement(case, "error", message="error").text = xml_text(msg)
    pathlib.Path(path).parent.mkdir(parents=True, exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)
