#!/usr/bin/env python3
"""Tests of the scripts the suite and the users rely on (run by CTest in the workspace environment):

- test_summary.py: a failure, an unreadable or empty result file, a CTest-failed test and a missing
  expected suite each fail the run; all present and passing passes;
- bag_check.py and report.py: a complete railvib bag passes; an incomplete one (a stream that sent
  no block, one without its end, a recorder that stopped on disk full) is reported with exit 1 and
  every stream named; a foreign bag, railvib names with other types, a bag with only /tf_static, a
  malformed block, a truncated or empty file are refused with exit 2 (report: non-zero, no traceback);
- launch_scenario.py's verdict: only a run whose recorder ends first and cleanly passes;
- the non-stream message contract (scripts/railvib_contracts.py) on every case of the table the core
  is held to, and the bag check refusing a recorded metrics or transform message that breaks it;
- compare.py: a house run whose soil, floors and section move at half the free run's shows
  -6.02 dB in every one-third-octave band and half the PPV (the metrics are linear in the record);
  a bag without the house is refused with its name, without a traceback;
- report.py's figures: a sine of amplitude A lasting T has a transform peak of A T / 2; the KB_F
  lines are the live sensors' A_u / A_o (an older bag's: `railvib_tool din-guides` of the recorded
  period); impact times are the wheels' defect crossings; the governing component is plotted; KB_FTr
  is the tool's; scenario.yaml is the recorded config; a bag without the record still reports;
- nothing outlives the launcher (launch_scenario.py): its master and nodes end when it is killed with
  SIGKILL, when the ./railvib that started it is, and on SIGTERM when it was started with SIGINT
  ignored (nohup, `&`); railvib_process.stop ends a process that ignores SIGINT and SIGTERM;
- the railvib script's workspace: two commands building at once take turns (the build lock), and a
  failed build shows the compiler's error lines, not every line holding the word "error".

usage: test_scripts.py [JUNIT_XML]
"""
import json
import math
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "scripts"
sys.path.insert(0, str(SCRIPTS))
import bag_check  # noqa: E402
sys.path.insert(0, str(ROOT / "test" / "ros"))
from junit_xml import run_verbose, write_junit  # noqa: E402
import launch_scenario  # noqa: E402
import node_fuzz  # noqa: E402
import railvib_names as names  # noqa: E402
import railvib_process  # noqa: E402
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

    def test_a_failure_log_with_control_characters_stays_a_readable_failure(self):
        # A node's log, as ROS colours it, with a stray NUL: the result file must parse and count the failure
        # (CI once read "not well-formed (invalid token)" and lost the failing case's log).
        log = "\x1b[31m[ERROR] [1.0]: soil: bad block\x1b[0m\x00 end\x07"
        d = WORK / "results_control_characters"
        shutil.rmtree(d, ignore_errors=True)
        node_fuzz.write_junit([{"group": "soil loads", "case": "nan", "outcome": "crash", "detail": "exit -6",
                                "log": log, "seconds": 1.0}], d / "san-node-fuzz.xml")

        class Failing(unittest.TestCase):
            def test_it(self):
                self.fail(log)
        with open(os.devnull, "w") as quiet:
            result = unittest.TextTestRunner(stream=quiet).run(
                unittest.defaultTestLoader.loadTestsFromTestCase(Failing))
        write_junit(result, "s", Failing, d / "script-tests.xml")
        for name in ("san-node-fuzz", "script-tests"):
            text = ET.parse(d / f"{name}.xml").getroot().find("testcase").find("failure").text
            self.assertIn("[ERROR] [1.0]: soil: bad block\\x00 end\\x07", text)
            self.assertNotIn("\x1b", text)
        rows, passed, failed, _ = test_summary.summarize([d], [], ["san-node-fuzz", "script-tests"])
        self.assertEqual((passed, failed), (0, 2), rows)

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
        for stem in ("scenario-checks", "node-fuzz", "robustness-cases", "tool-commands", "script-tests", "export-tests", "monitor-tests", "property-tests"):
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
    m = stream(rm.SoilLoads, first, count, 3, eos, 5e-4, [("force_n", 1)], "sleeper_count")
    m.seats_per_sleeper = 1  # the half track: one force per sleeper
    return m


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


def house_bag(path, scale, with_house=True, coupling=None):
    """A 2 s record at 1000 Hz of two ground sensors and the two floors, the surface receivers (the
    house's response point among them), and the section through the house: every signal is `scale`
    x the same decaying 20 Hz impact at 0.5 s. With `coupling`, a scenario record saying the run's
    building.coupling."""
    fs, n = 1000.0, 2000
    wave = [0.0 if k < 500 else 1e-3 * math.exp(-(k - 500) / fs / 0.05) * math.sin(2 * math.pi * 20 * (k - 500) / fs)
            for k in range(n)]
    sensors = ["ground_2m", "ground_8m"] + (["house_ground_floor", "house_first_floor"] if with_house else [])
    receivers = ["line_y1", names.BUILDING_RESPONSE_FREE_FIELD_POINT, "bldg_front_mid", "bldg_back_mid"]
    rec_y = [1.0, 8.0, 4.7, 11.7]
    msgs = []
    if coupling:
        msgs.append((names.SCENARIO, String(data=f"railvib_version: test\nconfig:\n  building:\n    coupling: {coupling}\n")))
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
        # The animation: a frame per 10 ms snapshot over the 0.3 s window around the four chosen times
        # (0.09 s apart), 10 frames per second, looping; the frames differ as the wave passes.
        from PIL import Image, ImageChops
        with Image.open(WORK / "cmp" / "section.gif") as gif:
            self.assertIn(gif.n_frames, (39, 40))
            self.assertEqual((gif.info["duration"], gif.info["loop"]), (100, 0))
            frames = []
            for k in (0, gif.n_frames // 2):
                gif.seek(k)
                frames.append(gif.convert("RGB"))
            self.assertIsNotNone(ImageChops.difference(*frames).getbbox(), "the animation does not change")
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

    def test_the_legends_name_what_differs_between_the_runs(self):
        day, night = report_bag(WORK / "cmp_day.bag", "day"), report_bag(WORK / "cmp_night.bag", "night")
        out = self.run_compare(day, night, WORK / "cmp_periods")
        self.assertEqual(out.returncode, 0, out.stderr)
        result = json.loads((WORK / "cmp_periods" / "compare.json").read_text())
        self.assertEqual(result["differences"], [{"key": "virtual_sensors.din4150_2_period", "a": "day", "b": "night"}])
        self.assertEqual(result["legend"], ["cmp_day.bag: virtual_sensors.din4150_2_period=day",
                                            "cmp_night.bag: virtual_sensors.din4150_2_period=night"])
        self.assertIn("| virtual_sensors.din4150_2_period | day | night |",
                      (WORK / "cmp_periods" / "compare.md").read_text())
        # The same scenario twice says so; a bag without its record says that it is not known.
        out = self.run_compare(day, day, WORK / "cmp_same")
        result = json.loads((WORK / "cmp_same" / "compare.json").read_text())
        self.assertEqual((result["differences"], result["legend"][0]), ([], "cmp_day.bag (same scenario)"))

    def test_two_runs_without_the_house_are_compared_sensor_by_sensor(self):
        # Any two runs: the metrics are linear in the record, so half the motion halves PPV and KB_Fmax.
        loud = house_bag(WORK / "cmp_loud.bag", 1.0, with_house=False)
        quiet = house_bag(WORK / "cmp_quiet.bag", 0.5, with_house=False)
        out = self.run_compare(loud, quiet, WORK / "cmp_runs")
        self.assertEqual(out.returncode, 0, out.stderr)
        result = json.loads((WORK / "cmp_runs" / "compare.json").read_text())
        self.assertEqual(sorted(result["sensors"]), ["ground_2m", "ground_8m"])
        for sensor, r in result["sensors"].items():
            for q in ("ppv_z_mm_s", "vector_ppv_mm_s", "kb_fmax"):
                self.assertAlmostEqual(r["b"][q] / r["a"][q], 0.5, places=9, msg=(sensor, q))
            self.assertAlmostEqual(r["b"]["dominant_frequency_z_hz"], r["a"]["dominant_frequency_z_hz"], places=9)
        self.assertGreater((WORK / "cmp_runs" / "sensors.png").stat().st_size, 10000)
        self.assertIn("| ground_2m | ppv_z_mm_s |", (WORK / "cmp_runs" / "compare.md").read_text())

    def test_the_recorded_couplings_decide_the_order_and_the_kind_of_comparison(self):
        # The free-field (one_way) run comes first: the swapped pair is refused, not labelled wrongly.
        free = house_bag(WORK / "cmp_rec_free.bag", 1.0, coupling="one_way")
        house = house_bag(WORK / "cmp_rec_house.bag", 0.5, coupling="two_way")
        out = self.run_compare(house, free, WORK / "cmp_swapped")
        self.assertNotEqual(out.returncode, 0)
        self.assertIn("give the free-field (one_way) run first", out.stderr)
        self.assertNotIn("Traceback", out.stderr)
        out = self.run_compare(free, house, WORK / "cmp_rec")
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertIn("soil under the house", json.loads((WORK / "cmp_rec" / "compare.json").read_text())["records"])
        # Two two-way runs (e.g. two speeds) are not a house-effect pair: sensor by sensor.
        other = house_bag(WORK / "cmp_rec_house2.bag", 0.25, coupling="two_way")
        out = self.run_compare(house, other, WORK / "cmp_rec_two")
        self.assertEqual(out.returncode, 0, out.stderr)
        result = json.loads((WORK / "cmp_rec_two" / "compare.json").read_text())
        self.assertAlmostEqual(result["sensors"]["ground_2m"]["b"]["ppv_z_mm_s"] /
                               result["sensors"]["ground_2m"]["a"]["ppv_z_mm_s"], 0.5, places=9)

    def test_a_measured_record_is_aligned_and_compared_band_by_band(self):
        # The run's ground_2m at 1000 Hz; the "measured" record: half of it, at 2000 Hz, starting 0.3 s into
        # the run. Aligned by cross-correlation, the run is twice the record: +6.02 dB in every loud band.
        run = house_bag(WORK / "cmp_meas_run.bag", 1.0, with_house=False)
        fs = 2000.0
        t = np.arange(0.0, 1.5, 1.0 / fs) + 0.3
        wave = np.where(t < 0.5, 0.0, 1e-3 * np.exp(-(t - 0.5) / 0.05) * np.sin(2 * np.pi * 20 * (t - 0.5)))
        record = WORK / "measured_velocity.csv"
        np.savetxt(record, np.c_[t - 0.3, 0.5 * wave], delimiter=",", header="t_s,vz", comments="", fmt="%.12g")
        out = subprocess.run([sys.executable, str(SCRIPTS / "compare.py"), str(record), str(run), str(WORK / "cmp_meas"),
                              "--sensor", "ground_2m"], capture_output=True, text=True)
        self.assertEqual(out.returncode, 0, out.stderr)
        result = json.loads((WORK / "cmp_meas" / "compare.json").read_text())
        self.assertAlmostEqual(result["measured_offset_s"], 0.3, delta=0.0011)
        r = result["sensors"]["ground_2m"]
        self.assertAlmostEqual(r["b"]["ppv_z_mm_s"] / r["a"]["ppv_z_mm_s"], 2.0, delta=0.02)
        self.assertAlmostEqual(r["b"]["kb_fmax"] / r["a"]["kb_fmax"], 2.0, delta=0.02)
        loud = [b for b in result["bands_z"] if b["a_db"] > 40.0]
        self.assertGreaterEqual(len(loud), 5)
        for b in loud:
            self.assertAlmostEqual(b["difference_db"], 6.02, delta=0.2, msg=b)
        md = (WORK / "cmp_meas" / "compare.md").read_text()
        self.assertIn("simulated - measured [dB]", md)
        self.assertIn("largest cross-correlation of v_z", md)
        # Refused with the reason: no such sensor; a record that is not a velocity CSV; no overlap.
        for first, options, message in ((record, ["--sensor", "attic"], "the run has no such sensor"),
                                        (run, ["--sensor", "ground_2m"], "a measured record goes first"),
                                        (record, ["--sensor", "ground_2m", "--offset-s", "5"], "at least 1 s is needed")):
            args = [first, run, WORK / "cmp_meas_bad"] + options
            out = subprocess.run([sys.executable, str(SCRIPTS / "compare.py")] + [str(x) for x in args],
                                 capture_output=True, text=True)
            self.assertNotEqual(out.returncode, 0, args)
            self.assertIn(message, out.stderr, args)
            self.assertNotIn("Traceback", out.stderr, args)

    def test_an_output_path_that_is_a_file_is_refused_by_every_script(self):
        bag = house_bag(WORK / "cmp_outfile.bag", 1.0, with_house=False)
        a_file = WORK / "not_a_directory"
        a_file.write_text("x")
        for script, args in (("report.py", [bag, a_file]), ("export.py", [bag, a_file]),
                             ("compare.py", [bag, bag, a_file]), ("study.py", ["--outdir", a_file, "--vary", "speed=1,2"])):
            r = subprocess.run([sys.executable, str(SCRIPTS / script)] + [str(x) for x in args], capture_output=True,
                               text=True, timeout=120)
            self.assertNotEqual(r.returncode, 0, script)
            self.assertIn("exists and is not a directory", r.stderr, script)
            self.assertNotIn("Traceback", r.stderr, script)
            self.assertEqual(a_file.read_text(), "x", script)

    def test_a_bag_without_sensors_is_refused(self):
        loud = house_bag(WORK / "cmp_loud2.bag", 1.0, with_house=False)
        bare = track_bag(WORK / "cmp_track.bag", [contact(0, 10, True)], [loads(0, 10, True)])
        out = self.run_compare(loud, bare, WORK / "cmp_bare")
        self.assertNotEqual(out.returncode, 0)
        self.assertIn("no /sensor_samples to compare", out.stderr)
        self.assertNotIn("Traceback", out.stderr)


class LaunchArguments(unittest.TestCase):
    def test_conflicting_or_impossible_arguments_are_refused_before_anything_starts(self):
        refused = {("soil_ranks:=0",): "soil_ranks:=0: a whole number of MPI ranks",
                   ("soil_ranks:=two",): "soil_ranks:=two",
                   ("soil_ranks:=-1",): "soil_ranks:=-1",
                   ("coupling:=two_way", "building:=false"): "two-way coupling is the house acting on the soil",
                   ("building:=maybe",): "building:=maybe: true or false",
                   ("part:=middle",): "part:=middle"}
        for args, message in refused.items():
            self.assertIn(message, launch_scenario.conflicting_arguments(list(args)) or "", args)
        for args in (["soil_ranks:=2"], ["coupling:=one_way", "building:=false"], ["coupling:=two_way"], [],
                     ["building:=false"], ["part:=upstream"]):
            self.assertIsNone(launch_scenario.conflicting_arguments(args), args)
        # Through the launcher: exit 2 and the reason, no master started.
        r = subprocess.run([sys.executable, str(SCRIPTS / "launch_scenario.py"), "railvib", "haren.launch",
                            "soil_ranks:=0"], capture_output=True, text=True, timeout=60)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("railvib: launch failed: soil_ranks:=0", r.stderr)
        self.assertNotIn("started", r.stdout)


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


# ------------------------------------------------------------------ report figures (issue #13)
import numpy as np  # noqa: E402
import yaml  # noqa: E402

# A synthetic Haren-like run: two wheels over a defect at x = 0.25 m, two sensors, a receiver line.
REPORT_SPEED_M_S = 8.0
REPORT_FRONT_START_M = -2.0
REPORT_AXLE_OFFSETS_M = [0.0, 1.6]
REPORT_DEFECT_M = 0.25
# What yaml-cpp writes: 1e-05 (no dot) is a number for railvib, a string for YAML 1.1.
REPORT_SCENARIO_TEXT = """railvib_version: test-1.2.3
command_line: ./railvib run haren speed:=8.0
config_file: /work/config/haren.yaml
launch_arguments:
  speed: "8.0"
  foundation: ""
config_overrides:
  - simulation.duration_s=1.0
host: testhost
recorded_utc: 2026-12-02T10:00:00Z
config:
  simulation:
    speed_m_s: 8.0
    time_step_s: 1e-05
  vehicle:
    name: tram
  vehicles:
    tram:
      wheels:
        - {name: lead_axle, radius_m: 0.34}
        - {name: trail_axle, radius_m: 0.34}
  unevenness:
    defect:
      enabled: true
      position_m: 0.25
      height_m: 1.0e-3
  soil:
    mesh:
      f_max_hz: 37.5
  site:
    rail_gauge_m: 1.435
    building:
      front_wall_distance_from_rail_m: 4.0
      center_x_m: 0.0
  building:
    width_m: 7.0
  virtual_sensors:
    din4150_2_period: PERIOD
"""
REPORT_CONFIG = {
    "simulation": {"speed_m_s": 8.0, "time_step_s": 1e-05},
    "vehicle": {"name": "tram"},
    "vehicles": {"tram": {"wheels": [{"name": "lead_axle", "radius_m": 0.34},
                                     {"name": "trail_axle", "radius_m": 0.34}]}},
    "unevenness": {"defect": {"enabled": True, "position_m": 0.25, "height_m": 1.0e-3}},
    "soil": {"mesh": {"f_max_hz": 37.5}},
    "site": {"rail_gauge_m": 1.435, "building": {"front_wall_distance_from_rail_m": 4.0, "center_x_m": 0.0}},
    "building": {"width_m": 7.0},
    "virtual_sensors": {"din4150_2_period": "day"},
}


def metrics_without_guides():
    """railvib/VibrationMetrics as recorded before it had the DIN 4150-2 guide values."""
    import genpy.dynamic
    text = "\n".join(line for line in rm.VibrationMetrics._full_text.splitlines()
                     if not line.startswith("float64 din4150_2_a_"))
    return genpy.dynamic.generate_dynamic("railvib/VibrationMetrics", text)["railvib/VibrationMetrics"]


def report_bag(path, scenario="day", guides=(0.123, 0.456), spikes_s=None):
    """1 s of the synthetic run. scenario: the DIN 4150-2 period of the recorded scenario, or None
    for a bag without /railvib/scenario; guides: the live sensors' A_u, A_o, or None for metrics of
    the older message; spikes_s: per wheel, the time of a force spike (no defect crossing)."""
    msgs = []
    if scenario:
        msgs.append((names.SCENARIO, String(data=REPORT_SCENARIO_TEXT.replace("PERIOD", scenario))))
    # Contact forces at 10 kHz: 25 kN static, a decaying impact once a wheel is past the defect.
    fc, n = 10000.0, 10000
    t = np.arange(n) / fc
    x = np.array([REPORT_FRONT_START_M - o + REPORT_SPEED_M_S * t for o in REPORT_AXLE_OFFSETS_M]).T
    f = np.full_like(x, 25e3)
    for w in range(2):
        if spikes_s:
            f[int(round(spikes_s[w] * fc)), w] += 30e3
            x[:, w] = 100.0 + t  # never over the defect
        else:
            after = np.clip(t - (REPORT_DEFECT_M - x[0, w]) / REPORT_SPEED_M_S, 0.0, None)
            f[:, w] += np.where(after > 0, 20e3 * np.exp(-after / 0.004) * np.sin(2 * np.pi * 60 * after), 0.0)
    for first in range(0, n, 2500):
        m = rm.ContactForces()
        m.first_sample_index, m.sample_count, m.sample_period_s, m.wheel_count = first, 2500, 1 / fc, 2
        m.end_of_stream = first + 2500 == n
        m.position_m = x[first:first + 2500].ravel().tolist()
        m.force_n = f[first:first + 2500].ravel().tolist()
        m.unevenness_m = [0.0] * (2500 * 2)
        msgs.append((names.CONTACT_FORCES, m))
    # Sensors at 1 kHz: ground_2m vertical, the first floor mostly across the track (vy governs).
    fs, ns = 1000.0, 1000
    ts = np.arange(ns) / fs
    sensors = ["ground_2m", "house_first_floor"]
    v = np.zeros((ns, 2, 3))
    v[:, 0, 2] = 1e-3 * np.sin(2 * np.pi * 20 * ts)
    v[:, 1, 1] = 2e-3 * np.sin(2 * np.pi * 15 * ts)
    v[:, 1, 2] = 0.5e-3 * np.sin(2 * np.pi * 30 * ts)
    # The receiver line: a pulse leaving the track at the first impact, at 150 m/s.
    line_y = [1.0, 3.0, 5.0, 7.0, 9.0, 11.0, 13.0]
    receivers = [f"line_y{int(y)}" for y in line_y] + [names.BUILDING_RESPONSE_FREE_FIELD_POINT]
    t_hit = (REPORT_DEFECT_M - REPORT_FRONT_START_M) / REPORT_SPEED_M_S
    r = np.zeros((ns, len(receivers), 3))
    for j, y in enumerate(line_y + [8.2]):
        r[:, j, 2] = 1e-3 * np.exp(-((ts - t_hit - y / 150.0) / 0.01) ** 2) / y
    lay = rm.PointLayout()
    lay.names, lay.positions = receivers, [Point(0.0, y, 0.0) for y in line_y + [8.2]]
    msgs.append((names.SURFACE_POINTS, lay))
    for first in range(0, ns, 500):
        ss = rm.SensorSamples()
        ss.first_sample_index, ss.sample_count, ss.sample_period_s = first, 500, 1 / fs
        ss.end_of_stream = first + 500 == ns
        ss.sensor_count, ss.sensor_names = 2, sensors
        ss.velocity_m_s = v[first:first + 500].ravel().tolist()
        ss.acceleration_m_s2 = [0.0] * (500 * 2 * 3)
        msgs.append((names.SENSOR_SAMPLES, ss))
        sv = rm.SurfaceVelocities()
        sv.first_sample_index, sv.sample_count, sv.sample_period_s = first, 500, 1 / fs
        sv.end_of_stream = ss.end_of_stream
        sv.receiver_count = len(receivers)
        sv.velocity_m_s = r[first:first + 500].ravel().tolist()
        msgs.append((names.SURFACE_VELOCITIES, sv))
    for name, governing in (("ground_2m", 2), ("house_first_floor", 1)):
        m = (rm.VibrationMetrics if guides else metrics_without_guides())()
        m.sensor_name, m.kb_f_max, m.governing_component, m.din4150_2_verdict = name, 0.5, governing, 1
        m.kind = m.KIND_FLOOR if name.startswith("house") else m.KIND_FREE_FIELD
        if guides:
            m.din4150_2_a_u, m.din4150_2_a_o, m.din4150_2_a_r = guides[0], guides[1], 0.05
        msgs.append((names.SENSOR_METRICS, m))
    status = {"status": "closed: all streams complete",
              "expected_streams": [names.CONTACT_FORCES, names.SURFACE_VELOCITIES, names.SENSOR_SAMPLES]}
    return write_bag(path, msgs, status)


class MessageContracts(unittest.TestCase):
    """The non-stream message contract as the Python readers apply it (scripts/railvib_contracts.py):
    every case of the table the core is held to (test/data/message_contract_cases.json), and the bag
    check refusing a recorded message that breaks it."""

    @staticmethod
    def value(v):
        if isinstance(v, str) and v in ("nan", "inf", "-inf"):
            return float(v)
        if isinstance(v, str) and v.endswith((" bands", " levels")):
            n = int(v.split()[0])
            return [10.0 ** (k / 10.0) for k in range(n)] if v.endswith("bands") else [60.0] * n
        if isinstance(v, list):
            return [MessageContracts.value(x) for x in v]
        return v

    def test_every_case_of_the_shared_table(self):
        import types
        import railvib_contracts as contracts
        table = json.loads((ROOT / "test" / "data" / "message_contract_cases.json").read_text())
        limit, sensors = table["velocity_limit_m_s"], table["sensors"]
        refused = 0
        for case in table["cases"]:
            fields = {k: self.value(v) for k, v in dict(table["valid"][case["kind"]], **case["set"]).items()}
            m = types.SimpleNamespace(**fields)
            kind = case["kind"]
            if kind == "metrics":
                problem = contracts.metrics_problem("/sensor_metrics", m, limit, sensors)
            elif kind == "surface":
                problem = contracts.surface_snapshot_problem("/surface_snapshot", m, limit)
            elif kind == "section":
                problem = contracts.section_snapshot_problem("/section_snapshot", m, limit)
            else:
                problem = contracts.transform_problem("/tf", m.parent, m.child, m.translation_m, m.rotation_xyzw)
            label = f"{kind}: {case['name']}"
            if case["refused"] is None:
                self.assertIsNone(problem, label)
            else:
                refused += 1
                self.assertIsNotNone(problem, label)
                self.assertIn(case["refused"], problem, label)
                self.assertTrue(problem.startswith("topic /"), label)
        self.assertGreaterEqual(refused, 40)

    def metrics_bag(self, path, **changes):
        msgs = [(names.CONTACT_FORCES, contact(0, 5, True)), (names.SOIL_LOADS, loads(0, 4, True))]
        lay = rm.SleeperLayout()
        lay.position_m = [0.0, 0.72, 1.44]
        msgs.append((names.SLEEPER_LAYOUT, lay))
        m = rm.VibrationMetrics(sensor_name="ground_2m", kind=0, kb_f=0.1, kb_f_max=0.2, ppv_m_s=1e-3,
                                ppv_vertical_m_s=1e-3, governing_component=2, governing_ppv_m_s=1e-3,
                                din4150_2_a_u=0.15, din4150_2_a_o=3.0, din4150_2_verdict=3, din4150_3_verdict=3,
                                verdict=3)
        for key, value in changes.items():
            setattr(m, key, value)
        msgs.append((names.SENSOR_METRICS, m))
        from geometry_msgs.msg import TransformStamped
        t = TransformStamped()
        t.header.frame_id, t.child_frame_id = "track", "building"
        t.transform.rotation.w = 1.0
        msgs.append(("/tf_static", TFMessage(transforms=[t])))
        status = {"status": "closed: all streams complete", "expected_streams": [names.CONTACT_FORCES,
                                                                                   names.SOIL_LOADS]}
        return write_bag(path, msgs, status)

    def test_the_bag_check_refuses_a_recorded_message_that_breaks_it(self):
        self.assertEqual(bag_check.check_bag(self.metrics_bag(WORK / "metrics_ok.bag")).code, 0)
        r = bag_check.check_bag(self.metrics_bag(WORK / "metrics_nan.bag", kb_f=float("nan")))
        self.assertEqual(r.code, 2)
        self.assertIn("/sensor_metrics: kb_f = nan", r.refused)
        r = bag_check.check_bag(self.metrics_bag(WORK / "metrics_verdict.bag", verdict=12))
        self.assertIn("verdict = 12", r.refused)
        bag = self.metrics_bag(WORK / "tf_bad.bag")
        from geometry_msgs.msg import TransformStamped
        t = TransformStamped()
        t.header.frame_id, t.child_frame_id = "track", "sensor_x"
        t.transform.rotation.w = 3.0
        with rosbag.Bag(str(bag), "a") as b:
            b.write("/tf", TFMessage(transforms=[t]), rospy.Time(1))
        r = bag_check.check_bag(bag)
        self.assertIn("transform 'track' -> 'sensor_x': rotation quaternion has norm 3", r.refused)


class ReportFigures(unittest.TestCase):
    """report.py's figures (issue #13): spectra, guide lines, impact times, zooms, scenario record, exposure."""

    def report(self, bag, *extra):
        out = WORK / (pathlib.Path(bag).stem + "_report")
        run = subprocess.run([sys.executable, str(SCRIPTS / "report.py"), str(bag), str(out)] + list(extra),
                             capture_output=True, text=True)
        self.assertEqual(run.returncode, 0, run.stdout + run.stderr)
        self.assertNotIn("Traceback", run.stderr)
        return out, json.loads((out / "report.json").read_text()), (out / "report.md").read_text()

    # The report of the default synthetic bag, per set of options: run once and read by every test that
    # checks a part of it (a report is ~2 s of CPU).
    _default_reports = {}

    def default_report(self, *extra):
        if extra not in ReportFigures._default_reports:
            bag = report_bag(WORK / f"rf_default_{len(ReportFigures._default_reports)}.bag")
            ReportFigures._default_reports[extra] = self.report(bag, *extra)
        return ReportFigures._default_reports[extra]

    def tool_json(self, *args):
        import report
        out = subprocess.run(report.tool() + list(args), capture_output=True, text=True)
        self.assertEqual(out.returncode, 0, out.stderr)
        return json.loads(out.stdout)

    def test_a_sine_of_amplitude_a_lasting_t_has_a_transform_peak_of_a_t_over_two(self):
        import report
        for amplitude, f_hz, duration_s, fs in ((2.5, 20.0, 1.5, 1000.0), (0.7, 12.25, 4.0, 500.0)):
            t = np.arange(int(duration_s * fs)) / fs
            fr, mag = report.spectrum(t, amplitude * np.sin(2 * np.pi * f_hz * t))
            k = int(np.argmax(mag))
            self.assertAlmostEqual(fr[k], f_hz, delta=1.0 / duration_s)
            self.assertAlmostEqual(mag[k] / (amplitude * duration_s / 2), 1.0, delta=0.02)
        self.assertEqual(report.spectrum_range_hz(1000.0, 2000.0), 100.0)
        self.assertAlmostEqual(report.spectrum_range_hz(100.0, 1000.0), 45.0)

    def test_the_spectra_share_one_range_and_mark_the_mesh_resolution(self):
        out, shown, md = self.default_report()
        self.assertEqual(shown["spectrum"]["range_hz"], [0.0, 100.0])
        self.assertEqual(shown["spectrum"]["mesh_f_max_hz"], 37.5)
        self.assertEqual(shown["spectrum"]["unit"], "(mm/s)/Hz")
        self.assertIn("|V(f)| = dt |FFT(v)|", md)
        self.assertIn("soil.mesh.f_max_hz = 37.5 Hz", md)
        for fig in ("contact_forces.png", "sensors.png", "wave_field.png", "building_vs_free_field.png"):
            self.assertIn(fig, shown["figures"])
            self.assertGreater((out / fig).stat().st_size, 10000, fig)

    def test_the_kbf_lines_are_the_live_sensors_guide_values(self):
        _, shown, md = self.report(report_bag(WORK / "rf_guides.bag", guides=(0.123, 0.456)))
        for name in ("ground_2m", "house_first_floor"):
            self.assertEqual((shown["sensors"][name]["a_u"], shown["sensors"][name]["a_o"]), (0.123, 0.456))
            self.assertIn(names.SENSOR_METRICS, shown["sensors"][name]["guide_source"])
        self.assertIn("0.123 / 0.456", md)

    def test_an_older_bag_draws_the_tools_guide_values_of_the_recorded_period(self):
        guides = self.tool_json("din-guides")["din4150_2_residential"]
        for period, scenario in (("night", "night"), ("day", "day"), ("day", None)):
            _, shown, _ = self.report(report_bag(WORK / f"rf_old_{scenario}.bag", scenario=scenario, guides=None))
            s = shown["sensors"]["ground_2m"]
            self.assertEqual((s["a_u"], s["a_o"]), (guides[period]["a_u"], guides[period]["a_o"]), scenario)
            self.assertIn("din-guides", s["guide_source"])
            self.assertEqual(s["period"], period)

    def test_impact_times_are_the_wheels_crossings_of_the_defect(self):
        out, shown, md = self.default_report()
        cf = shown["contact_forces"]
        expected = [(REPORT_DEFECT_M - REPORT_FRONT_START_M + o) / REPORT_SPEED_M_S for o in REPORT_AXLE_OFFSETS_M]
        for got, want in zip(cf["impact_times_s"], expected):
            self.assertAlmostEqual(got, want, delta=1e-6)
        self.assertEqual(cf["defect_position_m"], REPORT_DEFECT_M)
        self.assertEqual(cf["wheel_names"], ["lead_axle", "trail_axle"])
        self.assertIn("| 1 | trail_axle |", md)
        # the wave field zooms on the first impact and marks the house (4 m from the exterior rail, 7 m wide)
        wf = shown["wave_field"]
        self.assertAlmostEqual(wf["window_s"][0], expected[0] - 0.1, places=9)
        self.assertAlmostEqual(wf["window_s"][1] - wf["window_s"][0], 0.6, places=9)
        self.assertAlmostEqual(wf["house_y_m"][0], 0.7175 + 4.0, places=9)
        self.assertAlmostEqual(wf["house_y_m"][1], 0.7175 + 11.0, places=9)

    def test_without_the_defect_position_the_largest_force_deviation_is_used_and_said(self):
        spikes = [0.3141, 0.6]
        _, shown, md = self.report(report_bag(WORK / "rf_spikes.bag", scenario=None, spikes_s=spikes))
        cf = shown["contact_forces"]
        for got, want in zip(cf["impact_times_s"], spikes):
            self.assertAlmostEqual(got, want, delta=1e-9)
        self.assertEqual(cf["wheel_names"], ["axle 1", "axle 2"])
        self.assertIn("largest force deviation", md)
        self.assertIn("defect position is not known", md)

    def test_the_governing_component_is_plotted_beside_vz(self):
        _, shown, md = self.default_report()
        self.assertEqual(shown["sensors"]["ground_2m"]["plotted_components"], ["vz"])
        self.assertEqual(shown["sensors"]["house_first_floor"]["plotted_components"], ["vz", "vy"])
        self.assertIn("house_first_floor: vy", md)

    def test_the_standards_figure_draws_each_component_against_the_guideline_where_it_applies(self):
        out, shown, md = self.default_report()
        self.assertTrue((out / "standards.png").exists())
        self.assertIn("![standards.png](standards.png)", md)
        ground, floor = shown["standards"]["ground_2m"], shown["standards"]["house_first_floor"]
        self.assertEqual((ground["kind"], ground["guideline"]), ("free_field", "free field: not applicable"))
        self.assertEqual((floor["kind"], floor["guideline"]), ("floor", "floor values"))
        self.assertIsNone(ground["guideline_error"])
        self.assertGreaterEqual(ground["bands"], 10)
        # The synthetic sines: ground_2m v_z 1 mm/s at 20 Hz; the floor v_y 2 mm/s at 15 Hz, v_z 0.5 mm/s at 30 Hz
        # (a peak within 1 % of the amplitude at 1 kHz sampling; the frequency from the zero crossings).
        points = {(p["component"]): p for p in ground["ppv_points"]}
        self.assertEqual(set(points), {"z"})
        self.assertAlmostEqual(points["z"]["ppv_mm_s"], 1.0, delta=0.01)
        self.assertAlmostEqual(points["z"]["frequency_hz"], 20.0, delta=0.5)
        points = {(p["component"]): p for p in floor["ppv_points"]}
        self.assertEqual(set(points), {"y", "z"})
        self.assertAlmostEqual(points["y"]["ppv_mm_s"], 2.0, delta=0.02)
        self.assertAlmostEqual(points["y"]["frequency_hz"], 15.0, delta=0.5)
        self.assertAlmostEqual(points["z"]["frequency_hz"], 30.0, delta=0.8)

    def test_a_long_figure_title_is_wrapped_to_fit_the_figure(self):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import railvib_plots
        title = ("House response points (mid-width, 3/4 length) vs the soil under them (two-way; the free field "
                 "is the one_way run: ./railvib compare FREE.bag THIS.bag)")
        for width_in in (4.0, 8.0, 13.0):
            fig = plt.figure(figsize=(width_in, 3.0))
            lines = railvib_plots.fit_title(fig, title)
            extent = fig._suptitle.get_window_extent(fig.canvas.get_renderer())
            self.assertLessEqual(extent.width, 0.98 * width_in * fig.dpi, width_in)
            self.assertGreaterEqual(extent.x0, 0.0, width_in)
            self.assertEqual(lines > 1, width_in < 13.0, width_in)
            plt.close(fig)

    def test_the_exposure_rating_is_the_tools_on_the_recorded_samples(self):
        for extra, exposure_s in (((), 1.0), (("--exposure-s", "3600"), 3600.0)):
            out, shown, md = self.default_report(*extra)
            # Rated where the sensor stands: the free-field one is not judged, the floor one is.
            for name, kind in (("ground_2m", "free_field"), ("house_first_floor", "floor")):
                tool = self.tool_json("metrics", "--csv", str(out / f"{name}_velocity.csv"), "--column", "vx,vy,vz",
                                      "--exposure-s", str(exposure_s), "--period", "day", "--kind", kind)["din4150_2"]
                self.assertEqual(tool["verdict"] == "not applicable", kind == "free_field", tool)
                s = shown["sensors"][name]
                self.assertEqual((s["kb_ftr"], s["exposure_s"], s["rated_verdict"]),
                                 (tool["kb_ftr"], exposure_s, tool["verdict"]))
                self.assertIn(f"| {name} | 0.5000 | WARN (rating KB_FTr decides) | {tool['kb_ftr']:.3g} | "
                              f"{exposure_s:g} |", md)
            self.assertIn("only decides the WARN case", md)

    def test_the_scenario_is_shown_and_its_config_written(self):
        out, shown, md = self.default_report()
        self.assertTrue(shown["scenario_recorded"])
        self.assertEqual(yaml.safe_load((out / "scenario.yaml").read_text()), REPORT_CONFIG)
        for text in ("## Scenario", "test-1.2.3", "`./railvib run haren speed:=8.0`", "/work/config/haren.yaml",
                     "speed:=8.0", "simulation.duration_s=1.0", "testhost", "2026-12-02T10:00:00Z"):
            self.assertIn(text, md)
        self.assertNotIn("foundation:=", md)  # an empty argument keeps the config's value

    def test_a_bag_without_the_scenario_record_still_reports(self):
        out, shown, md = self.report(report_bag(WORK / "rf_noscenario.bag", scenario=None))
        self.assertFalse(shown["scenario_recorded"])
        self.assertIn("Not recorded (bag from an older railvib)", md)
        self.assertFalse((out / "scenario.yaml").exists())
        self.assertIsNone(shown["spectrum"]["mesh_f_max_hz"])
        self.assertIsNone(shown["contact_forces"]["defect_position_m"])
        self.assertEqual(shown["figures"], ["contact_forces.png", "sensors.png", "standards.png", "wave_field.png",
                                            "building_vs_free_field.png"][:len(shown["figures"])])
        self.assertEqual(len(shown["figures"]), 5)


FAKE_CATKIN_MAKE = r'''#!/bin/sh
# A stand-in for catkin_make: notes when it builds, fails if another build is inside the same tree.
ws="$(pwd)"
if [ -e "$ws/building" ]; then echo "two builds in $ws at once" >> "$ws/overlap"; fi
touch "$ws/building"
echo "start $(date +%s.%N)" >> "$ws/builds"
# What the compiler launcher would see: the arguments and the ccache settings in the environment.
echo "args $*" >> "$ws/launcher"
echo "CCACHE_BASEDIR=${CCACHE_BASEDIR:-unset} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-unset}" >> "$ws/launcher"
echo "nice $(ps -o ni= -p $$ | tr -d ' ')" >> "$ws/launcher"
mkdir -p "$ws/build" "$ws/devel" && touch "$ws/devel/setup.bash"
if [ -n "$FAKE_FAIL" ]; then
  # ninja's way of saying it (catkin_make --use-ninja)
  for i in $(seq 1 80); do echo "[$i/120] Building CXX object src/common/error_code.cpp.o -Werror=return-type"; done
  echo "FAILED: railvib/CMakeFiles/railvib_soil.dir/kernel.cpp.o"
  echo "/src/soil/kernel.cpp:42:7: error: 'stiffnes' was not declared in this scope"
  echo "   42 |       stiffnes += 1;"
  echo "      |       ^~~~~~~~"
  for i in $(seq 1 30); do echo "note: Error handling in unit $i"; done
  echo "ninja: build stopped: subcommand failed."
  rm -f "$ws/building"
  exit 2
fi
case "$ws" in *_san) sleep "${FAKE_SAN_BUILD_S:-1.5}" ;; *) sleep 1.5 ;; esac
echo "end $(date +%s.%N)" >> "$ws/builds"
rm -f "$ws/building"
'''


# A stand-in for ctest: notes when it ran and leaves time for a build beside it.
FAKE_CTEST = r'''#!/bin/sh
echo "start $(date +%s.%N)" >> "$FAKE_CTEST_LOG"
sleep 4
echo "end $(date +%s.%N)" >> "$FAKE_CTEST_LOG"
'''


class Workspace(unittest.TestCase):
    """The railvib script's build step with a stand-in for catkin_make (RAILVIB_CATKIN_MAKE), in a copy of
    the script whose workspace is a temporary folder."""

    def setUp(self):
        self.root = WORK / f"clone_{self._testMethodName}"
        self.root.mkdir(parents=True)
        shutil.copy(ROOT / "railvib", self.root / "railvib")
        fake = self.root / "fake_catkin_make"
        fake.write_text(FAKE_CATKIN_MAKE)
        fake.chmod(0o755)
        self.env = {**os.environ, "RAILVIB_CATKIN_MAKE": str(fake), "RAILVIB_CCACHE": "0"}

    def setup_command(self, **env):
        return subprocess.Popen(["bash", str(self.root / "railvib"), "setup"], env={**self.env, **env},
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def test_two_commands_building_at_once_take_turns(self):
        first, second = self.setup_command(), self.setup_command()
        outputs = [p.communicate(timeout=120) for p in (first, second)]
        for p, (out, err) in zip((first, second), outputs):
            self.assertEqual(p.returncode, 0, err)
        ws = self.root / ".ws"
        self.assertFalse((ws / "overlap").exists(), (ws / "overlap").read_text() if (ws / "overlap").exists() else "")
        times = [float(line.split()[1]) for line in (ws / "builds").read_text().splitlines()]
        kinds = [line.split()[0] for line in (ws / "builds").read_text().splitlines()]
        self.assertEqual(kinds, ["start", "end", "start", "end"])
        self.assertGreaterEqual(times[2], times[1])  # the second build began after the first had ended
        self.assertEqual(sum("waiting for it" in err for _, err in outputs), 1, outputs)

    def test_the_build_sees_the_ccache_settings_that_let_clones_share_the_cache(self):
        # The build runs under ccache with the clone as its base directory (paths hashed relative to it,
        # so a second clone hits the first one's cache), and without ccache when RAILVIB_CCACHE=0.
        if not shutil.which("ccache"):
            self.skipTest("ccache is not installed")
        p = self.setup_command(RAILVIB_CCACHE="1")
        _, err = p.communicate(timeout=120)
        self.assertEqual(p.returncode, 0, err)
        seen = (self.root / ".ws" / "launcher").read_text()
        self.assertIn("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", seen)
        self.assertIn(f"CCACHE_BASEDIR={self.root} CCACHE_NOHASHDIR=1", seen)
        (self.root / ".ws" / "launcher").unlink()
        p = self.setup_command(RAILVIB_CCACHE="0")
        p.communicate(timeout=120)
        seen = (self.root / ".ws" / "launcher").read_text()
        # Empty -D values clear a launcher cached by an earlier configure; catkin_make would hand -U to make.
        self.assertIn("-DCMAKE_CXX_COMPILER_LAUNCHER= ", seen)
        self.assertIn("-DCMAKE_C_COMPILER_LAUNCHER= ", seen)
        self.assertNotIn("-U", seen)

    def test_a_bad_master_port_is_refused_before_anything_is_built(self):
        for args in (["--port", "abc"], ["--port", "80"], ["--port=70000"], ["--port"]):
            r = subprocess.run(["bash", str(self.root / "railvib"), "run"] + args, env=self.env,
                               capture_output=True, text=True, timeout=60)
            self.assertEqual(r.returncode, 1, args)
            self.assertRegex(r.stderr, r"master port '.*': a number from 1024 to 65535|--port needs a number", args)
            self.assertFalse((self.root / ".ws" / "builds").exists(), args)

    def test_the_build_uses_ninja_and_reconfigures_a_tree_that_make_built(self):
        # CMake refuses to change a build tree's generator in place: the cache of a make-built workspace
        # goes (its objects stay, for ccache and the clean-up of later builds); a Ninja tree is kept.
        build = self.root / ".ws" / "build"
        (build / "CMakeFiles").mkdir(parents=True)
        (build / "CMakeCache.txt").write_text("CMAKE_GENERATOR:INTERNAL=Unix Makefiles\n")
        (build / "unit_tests").mkdir()
        p = self.setup_command()
        _, err = p.communicate(timeout=120)
        self.assertEqual(p.returncode, 0, err)
        self.assertIn("args --use-ninja ", (self.root / ".ws" / "launcher").read_text())
        self.assertFalse((build / "CMakeCache.txt").exists())
        self.assertFalse((build / "CMakeFiles").exists())
        self.assertTrue((build / "unit_tests").exists())
        # the command says where its time went (the phases it ran)
        self.assertRegex(err, r"railvib:\S* time: build \d+ min \d\d s; total \d+ min \d\d s")
        (build / "CMakeFiles").mkdir()
        (build / "CMakeCache.txt").write_text("CMAKE_GENERATOR:INTERNAL=Ninja\n")
        p = self.setup_command()
        _, err = p.communicate(timeout=120)
        self.assertEqual(p.returncode, 0, err)
        self.assertTrue((build / "CMakeCache.txt").exists())

    def test_the_sanitizer_build_compiles_beside_the_tests_at_the_lowest_priority(self):
        # ./railvib test: the Release build first, then the tests with the sanitizer build beside them at
        # nice 19 (it takes only the CPU the tests leave idle); its tests wait for it. Nothing here passes
        # (no test results, no sanitizer binaries), so the command must fail, and still say its phases.
        bin_dir = self.root / "bin"
        bin_dir.mkdir()
        (bin_dir / "ctest").write_text(FAKE_CTEST)
        (bin_dir / "ctest").chmod(0o755)
        log = self.root / "ctest_log"
        env = {**self.env, "RAILVIB_CTEST": str(bin_dir / "ctest"), "FAKE_CTEST_LOG": str(log),
               "FAKE_SAN_BUILD_S": "3"}
        r = subprocess.run(["bash", str(self.root / "railvib"), "test"], env=env, capture_output=True, text=True,
                           timeout=120)
        self.assertNotEqual(r.returncode, 0, r.stderr)
        ctest = [float(line.split()[1]) for line in log.read_text().splitlines()]
        release = (self.root / ".ws" / "builds").read_text().split()
        san = (self.root / ".ws_san" / "builds").read_text().split()
        self.assertLessEqual(float(release[3]), ctest[0])  # the Release build ended before the tests
        self.assertLess(float(san[1]), ctest[1])  # the sanitizer build began while they ran
        self.assertGreater(float(san[1]), float(release[3]))
        # The sanitizer build in two parts: what the node fuzz runs, then the unit tests; the fuzz starts
        # after the first part, at the command's priority, while the second part still compiles.
        self.assertEqual(san[0::2], ["start", "end", "start", "end"])
        # The nodes and the messages first, the unit tests second; never railvib_tool (the fuzz is given
        # the regular build's).
        san_args = [line for line in (self.root / ".ws_san" / "launcher").read_text().splitlines()
                    if line.startswith("args ")]
        self.assertEqual(len(san_args), 2, san_args)
        self.assertIn(" soil_node ", san_args[0] + " ")
        self.assertIn(" test_soil ", san_args[1] + " ")
        self.assertNotIn("railvib_tool", " ".join(san_args))
        fuzz_started = (self.root / ".ws_san" / "build" / "test_results" / "railvib" / "san-node-fuzz.log").stat().st_mtime
        self.assertGreater(fuzz_started, float(san[3]))
        self.assertLess(fuzz_started, float(san[7]))
        self.assertIn("nice 0", (self.root / ".ws" / "launcher").read_text())
        self.assertIn("nice 19", (self.root / ".ws_san" / "launcher").read_text())
        self.assertRegex(r.stderr, r"time: build .*, tests \(the sanitizer build beside them\) \d+ min \d\d s, "
                                   r"sanitizer build \(after the tests\) \d+ min \d\d s, sanitizer tests ")

    def test_the_test_command_interrupted_or_terminated_ends_the_build_beside_it(self):
        # The sanitizer build beside the tests is a background job (which ignores Ctrl-C): when the command
        # ends early, the build and everything it started end with it.
        bin_dir = self.root / "bin"
        bin_dir.mkdir()
        (bin_dir / "ctest").write_text(FAKE_CTEST)
        (bin_dir / "ctest").chmod(0o755)
        env = {**self.env, "RAILVIB_CTEST": str(bin_dir / "ctest"), "FAKE_CTEST_LOG": str(self.root / "ctest_log"),
               "FAKE_SAN_BUILD_S": "120"}
        for how, code in (("ctrl-c", 130), ("sigterm", 143)):
            shutil.rmtree(self.root / ".ws_san", ignore_errors=True)
            p = subprocess.Popen(["bash", str(self.root / "railvib"), "test"], env=env, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.PIPE, text=True, start_new_session=True)
            builds = self.root / ".ws_san" / "builds"
            deadline = time.monotonic() + 60
            while not builds.exists() and time.monotonic() < deadline:
                time.sleep(0.1)
            self.assertTrue(builds.exists(), how)
            if how == "ctrl-c":
                os.killpg(p.pid, signal.SIGINT)  # the terminal's Ctrl-C reaches the whole foreground group
            else:
                p.send_signal(signal.SIGTERM)
            _, err = p.communicate(timeout=60)
            self.assertEqual(p.returncode, code, f"{how}: {err}")
            time.sleep(0.5)
            left = subprocess.run(["pgrep", "-f", str(self.root)], capture_output=True, text=True).stdout.split()
            self.assertEqual(left, [], f"{how}: processes left running")
            self.assertNotIn("end", builds.read_text(), how)

    def test_a_failed_build_shows_the_compilers_error_lines(self):
        p = self.setup_command(FAKE_FAIL="1")
        _, err = p.communicate(timeout=120)
        self.assertEqual(p.returncode, 1)
        self.assertIn("kernel.cpp:42:7: error: 'stiffnes' was not declared in this scope", err)
        self.assertIn("stiffnes += 1;", err)  # the code line after the error
        self.assertIn("build failed; full log:", err)
        self.assertNotIn("error_code.cpp", err)
        self.assertNotIn("Error handling in unit 30", err)


IDLE_LAUNCH = """<launch>
  <param name="/railvib/config_file" value="{config}"/>
  <node pkg="railvib" type="site_frames_node" name="frames_a"/>
  <node pkg="railvib" type="site_frames_node" name="frames_b"/>
</launch>
"""


def processes_of_master(port):
    """PIDs of the live processes (not zombies) that belong to the master on PORT: the master itself and
    every process whose ROS_MASTER_URI names it."""
    from urllib.parse import urlparse
    found = []
    for d in pathlib.Path("/proc").iterdir():
        if not d.name.isdigit() or int(d.name) == os.getpid():
            continue
        try:
            if (d / "stat").read_text().split(")")[-1].split()[0] == "Z":
                continue
            cmd = (d / "cmdline").read_bytes().split(b"\0")
            env = (d / "environ").read_bytes().split(b"\0")
        except OSError:
            continue
        uris = [e[len(b"ROS_MASTER_URI="):].decode(errors="replace") for e in env if e.startswith(b"ROS_MASTER_URI=")]
        # roslaunch hands its nodes the master's URI with the host's name (http://HOST:PORT/)
        if any(urlparse(u).port == port for u in uris) or (b"rosmaster" in b" ".join(cmd) and str(port).encode() in cmd):
            found.append(int(d.name))
    return found


class LauncherTeardown(unittest.TestCase):
    """launch_scenario.py on a launch of two idle nodes, ended in the ways a user or a harness ends it."""

    def setUp(self):
        self.railvib_process = railvib_process
        self.port = railvib_process.free_port()
        self.launch = WORK / "idle.launch"
        self.launch.write_text(IDLE_LAUNCH.format(config=ROOT / "config" / "haren_ci.yaml"))
        self.env = {**os.environ, "ROS_MASTER_URI": f"http://localhost:{self.port}"}
        self.started = []

    def tearDown(self):
        for pid in processes_of_master(self.port):  # whatever a failed case left behind
            try:
                os.kill(pid, 9)
            except OSError:
                pass
        for p in self.started:
            if p.poll() is None:
                p.kill()
            p.wait()

    def start(self, command, ignore_sigint=False):
        def ignore():
            import signal
            signal.signal(signal.SIGINT, signal.SIG_IGN)
        p = subprocess.Popen(command, env=self.env, start_new_session=True, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True, preexec_fn=ignore if ignore_sigint else None)
        self.started.append(p)
        return p

    def launcher(self):
        return [sys.executable, str(SCRIPTS / "launch_scenario.py"), "-p", str(self.port), str(self.launch)]

    def wait_for_nodes(self):
        deadline = time.time() + 90
        while time.time() < deadline:
            listed = subprocess.run(["rosnode", "list"], env=self.env, capture_output=True, text=True, timeout=30)
            if {"/frames_a", "/frames_b"} <= set(listed.stdout.split()):
                pids = processes_of_master(self.port)
                commands = " ".join(pathlib.Path(f"/proc/{p}/cmdline").read_text() for p in pids)
                self.assertIn("__name:=frames_a", commands)
                self.assertIn("__name:=frames_b", commands)
                self.assertIn("rosmaster", commands)
                return pids
            time.sleep(0.2)
        self.fail("the idle launch did not come up")

    def assert_all_end(self, pids, within_s):
        deadline = time.time() + within_s
        while time.time() < deadline:
            alive = [p for p in pids if p in processes_of_master(self.port)]
            if not alive:
                return
            time.sleep(0.2)
        self.fail(f"still running {within_s} s later: {alive}")

    def test_the_launcher_killed_with_sigkill_leaves_nothing_running(self):
        launcher = self.start(self.launcher())
        pids = self.wait_for_nodes()
        launcher.kill()
        launcher.wait()
        self.assert_all_end(pids, 30.0)

    def test_the_launcher_ends_with_the_command_that_started_it(self):
        shell = self.start(["bash", "-c", " ".join(self.launcher()) + "; echo unreachable"])
        pids = self.wait_for_nodes()
        shell.kill()  # SIGKILL to the bash alone, as ./railvib run killed with kill -9
        shell.wait()
        self.assert_all_end(pids, 30.0)

    def test_started_with_sigint_ignored_a_harness_ends_it_within_its_grace(self):
        launcher = self.start(self.launcher(), ignore_sigint=True)
        pids = self.wait_for_nodes()
        t0 = time.time()
        out, _ = self.railvib_process.stop(launcher, grace_s=25.0, term_grace_s=10.0)
        self.assertLess(time.time() - t0, 25.0, out)  # SIGINT did it: no escalation needed
        self.assertEqual(launcher.returncode, 130, out)
        self.assertIn("railvib: launch interrupted", out)
        self.assertEqual(processes_of_master(self.port), [])
        self.assert_all_end(pids, 1.0)

    def test_sigterm_ends_the_launch_like_ctrl_c(self):
        launcher = self.start(self.launcher(), ignore_sigint=True)
        pids = self.wait_for_nodes()
        launcher.terminate()
        out, _ = launcher.communicate(timeout=40)
        self.assertIn("railvib: launch interrupted", out)
        self.assert_all_end(pids, 1.0)

    def test_the_site_frames_reach_tf_echo_and_a_tf2_python_listener(self):
        # What ROS users reach for (setup installs tf-tools and python3-tf2-ros): the house's frame in the
        # track frame, the same through a tf2 Python listener and `rosrun tf tf_echo`, in front of the track.
        launcher = self.start(self.launcher())
        self.wait_for_nodes()
        listener = subprocess.run([sys.executable, "-c", (
            "import rospy, tf2_ros\n"
            "rospy.init_node('tf2_listener_test', anonymous=True)\n"
            "buf = tf2_ros.Buffer(); tf2_ros.TransformListener(buf)\n"
            "t = buf.lookup_transform('track', 'building', rospy.Time(0), rospy.Duration(10.0)).transform.translation\n"
            "print(t.x, t.y, t.z)\n")], env=self.env, capture_output=True, text=True, timeout=60)
        self.assertEqual(listener.returncode, 0, listener.stderr)
        x, y, z = map(float, listener.stdout.split())
        self.assertTrue(3.0 < y < 20.0 and z == 0.0, (x, y, z))  # Haren's house: its front wall ~4.7 m off the axis
        echo = subprocess.Popen(["rosrun", "tf", "tf_echo", "track", "building"], env=self.env, text=True,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True)
        try:
            out, _ = echo.communicate(timeout=8)
        except subprocess.TimeoutExpired:
            out, _ = railvib_process.stop(echo, grace_s=5.0)
        self.assertIn(f"Translation: [{x:.3f}, {y:.3f}, {z:.3f}]", out)
        self.railvib_process.stop(launcher)

    def test_stop_escalates_to_sigkill_for_a_process_that_ignores_sigint_and_sigterm(self):
        stubborn = self.start([sys.executable, "-c", "import signal, sys, time\n"
                               "signal.signal(signal.SIGINT, signal.SIG_IGN)\n"
                               "signal.signal(signal.SIGTERM, signal.SIG_IGN)\n"
                               "print('ready', flush=True)\ntime.sleep(300)"])
        self.assertEqual(stubborn.stdout.readline().strip(), "ready")
        t0 = time.time()
        self.railvib_process.stop(stubborn, grace_s=1.0, term_grace_s=1.0)
        self.assertEqual(stubborn.returncode, -9)
        self.assertLess(time.time() - t0, 10.0)


CLASSES = (TestSummary, BagCheck, Compare, LaunchArguments, LaunchVerdict, MessageContracts, ReportFigures,
           Workspace, LauncherTeardown)


if __name__ == "__main__":
    suite = unittest.TestSuite()
    for cls in CLASSES:
        suite.addTests(unittest.defaultTestLoader.loadTestsFromTestCase(cls))
    result = run_verbose(suite)
    if len(sys.argv) > 1:
        write_junit(result, "script_tests", CLASSES, sys.argv[1])
    shutil.rmtree(WORK, ignore_errors=True)
    sys.exit(0 if result.wasSuccessful() else 1)
