#!/usr/bin/env python3
"""Tests of the scripts the suite and the users rely on (run by CTest in the workspace environment):

- test_summary.py: a failure, an unreadable or empty result file, a CTest-failed test and a missing
  expected suite each fail the run; all present and passing passes;
- bag_check.py and report.py: a complete railvib bag passes; an incomplete one (a stream that sent
  no block, one without its end, a recorder that stopped on disk full) is reported with exit 1 and
  every stream named; a foreign bag, railvib names with other types, a bag with only /tf_static, a
  malformed block, a truncated or empty file are refused with exit 2 (report: non-zero, no traceback);
- launch_scenario.py's verdict: only a run whose recorder ends first and cleanly passes;
- compare.py: a house run whose soil, floors and section move at half the free run's shows
  -6.02 dB in every one-third-octave band and half the PPV (the metrics are linear in the record);
  a bag without the house is refused with its name, without a traceback.

usage: test_scripts.py [JUNIT_XML]
"""
import json
import math
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "scripts"
sys.path.insert(0, str(SCRIPTS))
import bag_check  # noqa: E402
import launch_scenario  # noqa: E402
import railvib_names as names  # noqa: E402
import test_summary  # noqa: E402

import rosbag  # noqa: E402
import rospy  # noqa: E402
from geometry_msgs.msg import Point  # noqa: E402
from std_msgs.msg import String  # noqa: E402
from tf2_msgs.msg import TFMessage  # noqa: E402
import railvib.msg as rm  # noqa: E402

WORK = pathlib.Path(tempfile.mkdtemp(prefix="railvib_script_tests_"))


def junit(path, cases):
    """A JUnit file with (name, failed) cases."""
    suite = ET.Element("testsuite", name="s")
    for name, failed in cases:
        c = ET.SubElement(suite, "testcase", name=name)
        if failed:
            ET.SubElement(c, "failure", message="x")
    path.parent.mkdir(parents=True, exist_ok=True)
    ET.ElementTree(suite).write(path)


class TestSummary(unittest.TestCase):
    def run_summary(self, files, expect, failed_log=None):
        d = WORK / f"results_{self.id().split('.')[-1]}"
        shutil.rmtree(d, ignore_errors=True)
        for name, content in files.items():
            p = d / name
            if isinstance(content, str):
                p.parent.mkdir(parents=True, exist_ok=True)
                p.write_text(content)
            else:
                junit(p, content)
        args = ["test_summary.py", str(d), "--expect", ",".join(expect)]
        if failed_log:
            log = d / "failed.log"
            log.write_text(failed_log)
            args += ["--failed-log", str(log)]
        return test_summary.main(args)

    def test_all_present_and_passing_passes(self):
        self.assertEqual(self.run_summary({"gtest-a.xml": [("x", False)], "gtest-b.xml": [("y", False)]},
                                          ["gtest-a", "gtest-b"]), 0)

    def test_a_missing_expected_suite_fails(self):
        self.assertEqual(self.run_summary({"gtest-a.xml": [("x", False)]}, ["gtest-a", "gtest-b"]), 1)

    def test_a_failed_case_fails(self):
        self.assertEqual(self.run_summary({"gtest-a.xml": [("x", False), ("y", True)]}, ["gtest-a"]), 1)

    def test_unreadable_and_empty_result_files_fail(self):
        self.assertEqual(self.run_summary({"gtest-a.xml": "<testsuite><testcase"}, ["gtest-a"]), 1)
        self.assertEqual(self.run_summary({"gtest-a.xml": "<testsuite name='s'/>"}, ["gtest-a"]), 1)

    def test_a_test_ctest_saw_fail_fails(self):
        self.assertEqual(self.run_summary({"gtest-a.xml": [("x", False)]}, ["gtest-a"], "3:unit_soil\n"), 1)

    def test_no_result_at_all_fails(self):
        self.assertEqual(self.run_summary({}, []), 1)

    def test_the_default_list_names_every_registered_suite(self):
        cmake = (ROOT / "CMakeLists.txt").read_text()
        registered = cmake.split("foreach(domain", 1)[1].split(")", 1)[0].split()
        for domain in test_summary.UNIT_DOMAINS:
            self.assertIn(domain, registered)
        # ... and the other way: every domain with unit tests is expected (a missing one would pass).
        for domain in registered:
            if list((ROOT / "test" / "unit" / domain).glob("*.cpp")):
                self.assertIn(domain, test_summary.UNIT_DOMAINS, f"test/unit/{domain} is not an expected suite")
        for stem in ("scenario-checks", "node-fuzz", "robustness-cases", "tool-commands", "script-tests"):
            self.assertIn(stem, cmake, f"{stem} is expected but CMakeLists.txt does not write it")


# ------------------------------------------------------------------ bags
def stream(cls, first, count, points, eos, period, arrays, count_field):
    m = cls()
    m.header.stamp = rospy.Time.from_sec(first * period)
    m.first_sample_index, m.end_of_stream, m.sample_period_s, m.sample_count = first, eos, period, count
    setattr(m, count_field, points)
    for field, per in arrays:
        setattr(m, field, [1.0 + 0.1 * i for i in range(count * points * per)])
    return m


def contact(first, count, eos):
    return stream(rm.ContactForces, first, count, 2, eos, 1e-5,
                  [("position_m", 1), ("force_n", 1), ("unevenness_m", 1)], "wheel_count")


def loads(first, count, eos):
    return stream(rm.SoilLoads, first, count, 3, eos, 5e-4, [("force_n", 1)], "sleeper_count")


def write_bag(path, messages, status=None):
    """messages: (topic, msg); status: the recorder's JSON status, or None for none."""
    with rosbag.Bag(str(path), "w") as bag:
        t = rospy.Time(0, 1)
        for topic, msg in messages:
            bag.write(topic, msg, t)
        if status is not None:
            bag.write(names.RECORDING_STATUS, String(data=json.dumps(status)), t)
    return path


def track_bag(path, cf_blocks, sl_blocks, status="closed: all streams complete", layout=True):
    msgs = [(names.CONTACT_FORCES, b) for b in cf_blocks] + [(names.SOIL_LOADS, b) for b in sl_blocks]
    if layout:
        lay = rm.SleeperLayout()
        lay.position_m = [0.0, 0.72, 1.44]
        msgs.append((names.SLEEPER_LAYOUT, lay))
    st = None if status is None else {"status": status, "expected_streams": [names.CONTACT_FORCES, names.SOIL_LOADS]}
    return write_bag(path, msgs, st)


class BagCheck(unittest.TestCase):
    def check(self, path):
        return bag_check.check_bag(path)

    def test_a_complete_bag_passes(self):
        r = self.check(track_bag(WORK / "ok.bag", [contact(0, 5, False), contact(5, 5, True)],
                                 [loads(0, 4, True)]))
        self.assertEqual(r.code, 0, r.findings + [r.refused])

    def test_a_stream_that_sent_nothing_is_named(self):
        r = self.check(track_bag(WORK / "nosoil.bag", [contact(0, 5, True)], []))
        self.assertEqual(r.code, 1)
        self.assertEqual(r.incomplete, [names.SOIL_LOADS])

    def test_a_stream_without_its_end_and_a_failed_recorder_are_reported(self):
        r = self.check(track_bag(WORK / "cut.bag", [contact(0, 5, False)], [loads(0, 4, True)],
                                 status="failed: disk full: 0 MB free"))
        self.assertEqual(r.code, 1)
        self.assertEqual(r.incomplete, [names.CONTACT_FORCES])
        self.assertTrue(any("disk full" in f for f in r.findings), r.findings)

    def test_non_finite_values_are_findings(self):
        b = loads(0, 4, True)
        b.force_n[3] = float("nan")
        r = self.check(track_bag(WORK / "nan.bag", [contact(0, 5, True)], [b]))
        self.assertEqual(r.code, 1)
        self.assertTrue(any("not finite" in f for f in r.findings), r.findings)

    def test_a_gap_is_reported(self):
        r = self.check(track_bag(WORK / "gap.bag", [contact(0, 5, False), contact(7, 5, True)], [loads(0, 4, True)]))
        self.assertEqual(r.code, 1)
        self.assertTrue(any("samples 5..6 missing" in f for f in r.findings), r.findings)

    def test_malformed_blocks_are_refused(self):
        b = loads(0, 4, True)
        b.sleeper_count = 1000  # the bug the building node once trusted
        r = self.check(track_bag(WORK / "bad.bag", [contact(0, 5, True)], [b]))
        self.assertEqual(r.code, 2)
        self.assertIn("force_n has 12 values", r.refused)

    def test_legacy_bag_without_status_checks_the_scenario_streams(self):
        r = self.check(track_bag(WORK / "legacy.bag", [contact(0, 5, True)], [loads(0, 4, True)], status=None))
        self.assertEqual(r.code, 0, r.findings)
        self.assertEqual(r.expected, [names.CONTACT_FORCES, names.SOIL_LOADS])

    def test_foreign_bags_are_refused(self):
        foreign = write_bag(WORK / "foreign.bag", [("/chatter", String(data="hello"))])
        self.assertIn("not a railvib bag", self.check(foreign).refused)
        only_tf = write_bag(WORK / "tf_static.bag", [("/tf_static", TFMessage())])
        self.assertIn("not a railvib bag", self.check(only_tf).refused)
        wrong = write_bag(WORK / "wrong.bag", [(names.CONTACT_FORCES, String(data="x"))])
        self.assertIn("has type std_msgs/String", self.check(wrong).refused)

    def test_unreadable_files_are_refused(self):
        good = track_bag(WORK / "whole.bag", [contact(0, 5, True)], [loads(0, 4, True)])
        data = good.read_bytes()
        (WORK / "half.bag").write_bytes(data[: len(data) // 2])
        (WORK / "empty.bag").write_bytes(b"")
        (WORK / "text.bag").write_text("not a bag\n")
        for name in ("half.bag", "empty.bag", "text.bag", "missing.bag"):
            r = self.check(WORK / name)
            self.assertEqual(r.code, 2, name)
            self.assertIn("cannot read", r.refused)
        self.assertEqual(self.check(WORK).code, 2)  # a directory

    def test_the_report_refuses_or_reports_without_a_traceback(self):
        env = dict(os.environ)
        for name, bag, code, text in [
            ("foreign", write_bag(WORK / "rf.bag", [("/chatter", String(data="x"))]), 1, "not a railvib bag"),
            ("wrong types", write_bag(WORK / "rw.bag", [(names.SOIL_LOADS, String(data="x"))]), 1, "has type"),
            ("tf_static only", write_bag(WORK / "rt.bag", [("/tf_static", TFMessage())]), 1, "not a railvib bag"),
            ("incomplete", track_bag(WORK / "ri.bag", [contact(0, 5, True)], []), 1, names.SOIL_LOADS),
            ("complete", track_bag(WORK / "rc.bag", [contact(0, 5, True)], [loads(0, 4, True)]), 0, "report.md"),
        ]:
            out = subprocess.run([sys.executable, str(SCRIPTS / "report.py"), str(bag), str(WORK / (name + "_out"))],
                                 capture_output=True, text=True, env=env)
            self.assertEqual(out.returncode, code, name + ": " + out.stderr)
            self.assertIn(text, out.stdout + out.stderr, name)
            self.assertNotIn("Traceback", out.stderr, name)


def house_bag(path, scale, with_house=True):
    """A 2 s record at 1000 Hz of two ground sensors and the two floors, the surface receivers (the
    house's response point among them), and the section through the house: every signal is `scale`
    x the same decaying 20 Hz impact at 0.5 s."""
    fs, n = 1000.0, 2000
    wave = [0.0 if k < 500 else 1e-3 * math.exp(-(k - 500) / fs / 0.05) * math.sin(2 * math.pi * 20 * (k - 500) / fs)
            for k in range(n)]
    sensors = ["ground_2m", "ground_8m"] + (["house_ground_floor", "house_first_floor"] if with_house else [])
    receivers = ["line_y1", names.BUILDING_RESPONSE_FREE_FIELD_POINT, "bldg_front_mid", "bldg_back_mid"]
    rec_y = [1.0, 8.0, 4.7, 11.7]
    msgs = []
    layout = rm.PointLayout()
    layout.names = receivers if with_house else receivers[:1]
    layout.positions = [Point(0.0, y, 0.0) for y in rec_y[:len(layout.names)]]
    msgs.append((names.SURFACE_POINTS, layout))
    for first in range(0, n, 500):
        ss = rm.SensorSamples()
        ss.header.stamp = rospy.Time.from_sec(first / fs)
        ss.first_sample_index, ss.sample_count, ss.sample_period_s = first, 500, 1 / fs
        ss.end_of_stream = first + 500 == n
        ss.sensor_count, ss.sensor_names = len(sensors), sensors
        ss.velocity_m_s = [scale * wave[k] * (c == 2) for k in range(first, first + 500) for _ in sensors for c in range(3)]
        ss.acceleration_m_s2 = [0.0] * len(ss.velocity_m_s)
        msgs.append((names.SENSOR_SAMPLES, ss))
        sv = rm.SurfaceVelocities()
        sv.header.stamp = ss.header.stamp
        sv.first_sample_index, sv.sample_count, sv.sample_period_s = first, 500, 1 / fs
        sv.end_of_stream = ss.end_of_stream
        sv.receiver_count = len(layout.names)
        sv.velocity_m_s = [scale * wave[k] * (c == 2) for k in range(first, first + 500) for _ in layout.names
                           for c in range(3)]
        msgs.append((names.SURFACE_VELOCITIES, sv))
    for i, k in enumerate(range(0, n, 10)):
        sec = rm.SectionSnapshot()
        sec.header.stamp = rospy.Time.from_sec(k / fs)
        sec.sample_index, sec.x_m, sec.origin_y_m, sec.spacing_y_m, sec.ny = i, 0.0, -2.0, 1.0, 16
        sec.depth_m = [0.0, 0.5, 1.0, 2.0]
        sec.vertical_velocity_m_s = [scale * wave[k] * (1 + 0.1 * iy) for _ in sec.depth_m for iy in range(16)]
        msgs.append((names.SECTION_SNAPSHOT, sec))
    status = {"status": "closed: all streams complete", "expected_streams": [names.SURFACE_VELOCITIES, names.SENSOR_SAMPLES]}
    return write_bag(path, msgs, status)


class Compare(unittest.TestCase):
    def run_compare(self, free, house, out):
        return subprocess.run([sys.executable, str(SCRIPTS / "compare.py"), str(free), str(house), str(out)],
                              capture_output=True, text=True)

    def test_half_the_motion_is_six_decibels_in_every_band(self):
        free, house = house_bag(WORK / "cmp_free.bag", 1.0), house_bag(WORK / "cmp_house.bag", 0.5)
        out = self.run_compare(free, house, WORK / "cmp")
        self.assertEqual(out.returncode, 0, out.stderr)
        result = json.loads((WORK / "cmp" / "compare.json").read_text())
        self.assertEqual(result["figures"], ["floors_vs_free_field.png", "section_snapshots.png", "section.gif"])
        for f in result["figures"]:
            self.assertGreater((WORK / "cmp" / f).stat().st_size, 10000, f)
        rec = result["records"]
        self.assertAlmostEqual(rec["soil under the house"]["ppv_z_mm_s"] / rec["free field"]["ppv_z_mm_s"], 0.5,
                               places=9)
        for floor in ("house_ground_floor", "house_first_floor"):
            self.assertAlmostEqual(rec[floor + ", two-way"]["ppv_z_mm_s"] / rec[floor + ", one-way"]["ppv_z_mm_s"],
                                   0.5, places=9)
            self.assertAlmostEqual(rec[floor + ", one-way"]["kb_fmax"], rec["free field"]["kb_fmax"], places=9)
        loud = [b for b in result["bands"] if b["free_field_db"] > 40.0]  # the bands the impact fills
        self.assertGreaterEqual(len(loud), 5)
        for b in loud:  # 20 log10(0.5) = -6.02 dB; levels are printed to 0.01 dB
            self.assertAlmostEqual(b["under_house_db"] - b["free_field_db"], -6.02, delta=0.011, msg=b)

    def test_a_run_without_the_house_is_refused(self):
        free = house_bag(WORK / "cmp_free2.bag", 1.0)
        bare = house_bag(WORK / "cmp_bare.bag", 1.0, with_house=False)
        out = self.run_compare(free, bare, WORK / "cmp_bare")
        self.assertNotEqual(out.returncode, 0)
        self.assertIn("a run with the house is needed", out.stderr)
        self.assertIn("house_ground_floor", out.stderr)
        self.assertNotIn("Traceback", out.stderr)


class LaunchVerdict(unittest.TestCase):
    REQUIRED = {"vehicle", "track", "soil", "building", "virtual_sensor", "recorder", "master"}

    def verdict(self, deaths):
        return launch_scenario.verdict(deaths, self.REQUIRED, "recorder")

    def test_the_recorder_ending_first_and_cleanly_passes(self):
        self.assertTrue(self.verdict([("recorder-8", 0)])[0])
        self.assertTrue(self.verdict([("site_frames-1", 0), ("recorder-8", 0)])[0])

    def test_anything_else_fails(self):
        self.assertFalse(self.verdict([("building-5", 0), ("recorder-8", 0)])[0])  # killed by rosnode kill
        self.assertFalse(self.verdict([("soil-4", 1)])[0])  # refused its input or config
        self.assertFalse(self.verdict([("master", -9)])[0])
        self.assertFalse(self.verdict([("recorder-8", 1)])[0])  # incomplete streams, disk full
        self.assertFalse(self.verdict([("site_frames-1", 1), ("recorder-8", 0)])[0])
        self.assertFalse(self.verdict([])[0])  # interrupted
        self.assertFalse(self.verdict([("track-3", None)])[0])


def write_junit(result, path):
    suite = ET.Element("testsuite", name="script_tests", tests=str(result.testsRun))
    failed = {t.id(): m for t, m in result.failures + result.errors}
    for cls in (TestSummary, BagCheck, Compare, LaunchVerdict):
        for test in unittest.defaultTestLoader.loadTestsFromTestCase(cls):
            case = ET.SubElement(suite, "testcase", classname=cls.__name__, name=test.id().split(".")[-1])
            if test.id() in failed:
                ET.SubElement(case, "failure", message="failed").text = failed[test.id()]
    pathlib.Path(path).parent.mkdir(parents=True, exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)


if __name__ == "__main__":
    suite = unittest.TestSuite()
    for cls in (TestSummary, BagCheck, Compare, LaunchVerdict):
        suite.addTests(unittest.defaultTestLoader.loadTestsFromTestCase(cls))
    result = unittest.TextTestRunner(verbosity=2).run(suite)
    if len(sys.argv) > 1:
        write_junit(result, sys.argv[1])
    shutil.rmtree(WORK, ignore_errors=True)
    sys.exit(0 if result.wasSuccessful() else 1)
