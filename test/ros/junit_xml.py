"""JUnit XML of a unittest run (what scripts/test_summary.py and CTest's result folder read)."""
import pathlib
import unittest
import xml.etree.ElementTree as ET


def write_junit(result, suite_name, case_class, path):
    """One <testcase> per test of case_class (a TestCase class, or a sequence of them), with its failure or
    error text."""
    classes = case_class if isinstance(case_class, (list, tuple)) else (case_class,)
    suite = ET.Element("testsuite", name=suite_name, tests=str(result.testsRun),
                       failures=str(len(result.failures)), errors=str(len(result.errors)))
    failed = {t.id(): msg for t, msg in result.failures}
    errored = {t.id(): msg for t, msg in result.errors}
    for cls in classes:
        for test in unittest.defaultTestLoader.loadTestsFromTestCase(cls):
            case = ET.SubElement(suite, "testcase", classname=cls.__name__, name=test.id().split(".")[-1])
            if test.id() in failed:
                ET.SubElement(case, "failure", message="failed").text = failed[test.id()]
            if test.id() in errored:
                ET.SubElement(case, "error", message="error").text = errored[test.id()]
    pathlib.Path(path).parent.mkdir(parents=True, exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)
