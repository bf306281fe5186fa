#!/usr/bin/env python3
"""Tests of the exports and the study driver (run by CTest in the workspace environment):

- export.py: every sample of every stream is one CSV row with the bag's doubles read back exactly;
  the .mat file holds the same arrays; the surface and section snapshots become binary compressed
  VTK files (meshio) whose grid (origin, spacing, x-fastest order, z = -depth) and values (three
  components when recorded, the vertical alone otherwise) are the messages', indexed by a .pvd whose
  time steps are the snapshot stamps; a foreign bag is refused;
- bag_check.py: a per-sensor topic that lost a message is a finding, one of another type is refused;
- study.py: a grid is every combination; each run gets its launch arguments and a config file with
  its dotted keys over the base; the table holds each run's recorded metrics; a failed run fails the
  study and is named; bad keys and values are refused before any run;
- measured_record.py (./railvib import): a 20 Hz acceleration sine of known amplitude, from a CSV in g
  and from a 16-bit WAV, gives its velocity amplitude as PPV within 1 % (and within 0.1 % in the
  velocity CSV); the DIN 45669-1 test vectors (1 mm/s sines at 5.6, 16, 31.5 and 80 Hz) given as
  acceleration give the standard's KB_Fmax within 1 %; a velocity record in mm/s passes unchanged; a
  file that is no WAV, a missing channel, a non-uniform time step, a record too short, a value beyond
  the physical bound and contradictory options are refused with the reason, no traceback.

usage: test_exports.py [JUNIT_XML]
"""
import copy
import csv
import json
import math
import pathlib
import shutil
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "scripts"
sys.path.insert(0, str(SCRIPTS))
sys.path.insert(0, str(ROOT / "test" / "scripts"))
import bag_check  # noqa: E402
sys.path.insert(0, str(ROOT / "test" / "ros"))
from junit_xml import run_verbose, write_junit  # noqa: E402
import railvib_names as names  # noqa: E402
from railvib_paths import find_railvib_tool  # noqa: E402
import railvib_yaml  # noqa: E402

import rosbag  # noqa: E402
import rospy  # noqa: E402
import yaml  # noqa: E402
from geometry_msgs.msg import Vector3Stamped  # noqa: E402
from std_msgs.msg import String  # noqa: E402
import railvib.msg as rm  # noqa: E402

WORK = pathlib.Path(tempfile.mkdtemp(prefix="railvib_export_tests_"))
FS_HZ, SAMPLES = 1000.0, 600
# Snapshot values are velocities within limits.velocity_m_s (the message contract): 2^-10 m/s steps.
SNAP_SCALE = 2.0 ** -10
SENSORS = ["ground_2m", "house_first_floor"]
RECEIVERS = ["line_y1", "line_y8"]


def velocity(k, point, c):
    """A distinct, non-round value per sample, point and component (exact round trip is checked)."""
    return 1e-3 * math.sin(0.0123 * k + point) * (c + 1) / 3.0


BANDS_HZ = [8.0, 10.0, 12.5]


def metrics_message(sensor, i, r):
    """Sensor i's r-th metrics message: values that tell sensor and message apart, within the contract."""
    m = rm.VibrationMetrics()
    m.header.stamp = rospy.Time.from_sec(0.1 if r == 0 else (SAMPLES - 1) / FS_HZ)
    m.sensor_name = sensor
    m.kind = m.KIND_FREE_FIELD if i == 0 else m.KIND_FLOOR
    m.resolved_hz = 50.0
    m.kb_f = 0.01 * (i + 1) * (r + 1)
    m.kb_f_max = 0.02 * (i + 1) * (r + 1)
    m.ppv_m_s, m.ppv_vertical_m_s = 1e-3 * (i + r + 1), 5e-4 * (i + r + 1)
    m.governing_component, m.governing_ppv_m_s = 2, 5e-4 * (i + r + 1)
    m.dominant_frequency_hz, m.din4150_3_limit_m_s = 20.0 + i, 5e-3
    m.third_octave_center_hz = BANDS_HZ
    m.third_octave_level_db = [60.0 + 10 * i + r + b for b in range(len(BANDS_HZ))]
    m.din4150_2_a_u, m.din4150_2_a_o, m.din4150_2_a_r = 0.3, 6.0, 0.2
    m.din4150_2_verdict = m.VERDICT_NOT_APPLICABLE if i == 0 else m.VERDICT_OK
    m.din4150_3_verdict = m.din4150_2_verdict
    m.verdict = m.din4150_2_verdict
    return m


def export_bag(path, per_sensor_messages=True, drop_one=False, metrics_of=metrics_message):
    """Sensors and receivers at 1 kHz in blocks of 200, 3 surface and 3 section snapshots, a scenario record."""
    with rosbag.Bag(str(path), "w") as bag:
        t0 = rospy.Time(0, 1)
        layout = rm.PointLayout()
        layout.names = RECEIVERS
        from geometry_msgs.msg import Point
        layout.positions = [Point(0.0, 1.0, 0.0), Point(0.0, 8.0, 0.0)]
        bag.write(names.SURFACE_POINTS, layout, t0)
        for first in range(0, SAMPLES, 200):
            stamp = rospy.Time.from_sec(first / FS_HZ) if first else t0
            ss = rm.SensorSamples()
            ss.header.stamp = stamp
            ss.first_sample_index, ss.sample_count, ss.sample_period_s = first, 200, 1 / FS_HZ
            ss.end_of_stream = first + 200 == SAMPLES
            ss.sensor_count, ss.sensor_names = len(SENSORS), SENSORS
            ss.velocity_m_s = [velocity(k, i, c) for k in range(first, first + 200) for i in range(2) for c in range(3)]
            ss.acceleration_m_s2 = [10 * v for v in ss.velocity_m_s]
            bag.write(names.SENSOR_SAMPLES, ss, stamp)
            sv = rm.SurfaceVelocities()
            sv.header.stamp = stamp
            sv.first_sample_index, sv.sample_count, sv.sample_period_s = first, 200, 1 / FS_HZ
            sv.end_of_stream = ss.end_of_stream
            sv.receiver_count = 2
            sv.velocity_m_s = [velocity(k, 5 + i, c) for k in range(first, first + 200) for i in range(2)
                               for c in range(3)]
            bag.write(names.SURFACE_VELOCITIES, sv, stamp)
        if per_sensor_messages:
            for i, sensor in enumerate(SENSORS):
                for k in range(SAMPLES - (1 if drop_one and i == 1 else 0)):
                    v = Vector3Stamped()
                    v.header.stamp = rospy.Time.from_sec(k / FS_HZ) if k else t0
                    v.vector.x, v.vector.y, v.vector.z = (velocity(k, i, c) for c in range(3))
                    bag.write(names.sensor_topic(sensor, "velocity"), v, v.header.stamp)
        for s in range(3):
            stamp = rospy.Time.from_sec(0.1 * (s + 1))
            snap = rm.SurfaceSnapshot()
            snap.header.stamp = stamp
            snap.sample_index = s
            snap.origin_x_m, snap.origin_y_m, snap.spacing_x_m, snap.spacing_y_m = -2.0, 1.0, 0.5, 0.25
            snap.nx, snap.ny = 5, 4
            # Values of a ground's size (mm/s), exact in float32: SNAP_SCALE x (s + i + 10 j).
            snap.vertical_velocity_m_s = [SNAP_SCALE * (s + i + 10 * j) for j in range(4) for i in range(5)]  # x fastest
            # The horizontal components (frame track): vx = -2 x vz, vy = 3 x vz, each exact in float32.
            snap.velocity_x_m_s = [-2.0 * v for v in snap.vertical_velocity_m_s]
            snap.velocity_y_m_s = [3.0 * v for v in snap.vertical_velocity_m_s]
            bag.write(names.SURFACE_SNAPSHOT, snap, stamp)
            sec = rm.SectionSnapshot()
            sec.header.stamp = stamp
            sec.sample_index, sec.x_m, sec.origin_y_m, sec.spacing_y_m, sec.ny = s, 0.0, -3.0, 1.5, 3
            sec.depth_m = [0.0, 0.5, 1.5]
            sec.vertical_velocity_m_s = [SNAP_SCALE * (s + j + 100 * r) for r in range(3) for j in range(3)]  # y fastest
            bag.write(names.SECTION_SNAPSHOT, sec, stamp)
        for r in range(2):  # two metrics messages per sensor, the second as of the last sample
            for i, sensor in enumerate(SENSORS):
                m = metrics_of(sensor, i, r)
                bag.write(names.SENSOR_METRICS, m, m.header.stamp)
        bag.write(names.SCENARIO, String(data=yaml.safe_dump({"railvib_version": "test", "config": {"soil": {}}})), t0)
        status = {"status": "closed: all streams complete",
                  "expected_streams": [names.SURFACE_VELOCITIES, names.SENSOR_SAMPLES]}
        bag.write(names.RECORDING_STATUS, String(data=json.dumps(status)), rospy.Time.from_sec(SAMPLES / FS_HZ))
    return path


def run_script(script, *args):
    return subprocess.run([sys.executable, str(SCRIPTS / script)] + [str(a) for a in args],
                          capture_output=True, text=True)


class Export(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.bag = export_bag(WORK / "export.bag")
        cls.out = WORK / "export"
        cls.result = run_script("export.py", cls.bag, cls.out, "--what", "csv,mat,vtk")

    def test_it_succeeds(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr + self.result.stdout)

    def test_every_sample_is_one_row_with_the_bag_values_exactly(self):
        with open(self.out / "csv" / "sensor_samples.csv") as f:
            rows = list(csv.reader(f))
        header = rows[0]
        self.assertEqual(header[:4], ["t_s", "ground_2m_vx_m_s", "ground_2m_vy_m_s", "ground_2m_vz_m_s"])
        self.assertEqual(len(header), 1 + len(SENSORS) * 6)
        self.assertEqual(len(rows) - 1, SAMPLES)
        col = header.index("house_first_floor_vz_m_s")
        acol = header.index("house_first_floor_az_m_s2")
        for k in (0, 1, 199, 200, 377, SAMPLES - 1):
            self.assertEqual(float(rows[k + 1][0]), k / FS_HZ)
            self.assertEqual(float(rows[k + 1][col]), velocity(k, 1, 2))
            self.assertEqual(float(rows[k + 1][acol]), 10 * velocity(k, 1, 2))
        with open(self.out / "csv" / "surface_velocities.csv") as f:
            rows = list(csv.reader(f))
        col = rows[0].index("line_y8_vy_m_s")
        self.assertEqual(float(rows[451][col]), velocity(450, 6, 1))
        with open(self.out / "csv" / "surface_points.csv") as f:
            self.assertEqual(list(csv.reader(f))[2], ["line_y8", "0.0", "8.0", "0.0"])

    def test_the_mat_file_holds_the_same_arrays(self):
        import scipy.io
        mat = scipy.io.loadmat(str(self.out / "railvib.mat"), squeeze_me=True, struct_as_record=False)
        ss = mat["sensor_samples"]
        self.assertEqual(ss.velocity_m_s.shape, (SAMPLES, len(SENSORS), 3))
        self.assertEqual(ss.velocity_m_s[377, 1, 2], velocity(377, 1, 2))
        self.assertEqual(list(ss.sensor_names), SENSORS)
        self.assertAlmostEqual(ss.t_s[-1], (SAMPLES - 1) / FS_HZ, places=15)
        self.assertEqual(mat["surface_velocities"].velocity_m_s[450, 1, 1], velocity(450, 6, 1))

    def test_the_metrics_are_the_recorded_messages_per_sensor(self):
        # KB_F, PPV, verdicts and one-third-octave levels per sensor and message, as the core sent them.
        for i, sensor in enumerate(SENSORS):
            with open(self.out / "csv" / f"metrics_{sensor}.csv") as f:
                rows = list(csv.DictReader(f))
            self.assertEqual(len(rows), 2)
            for r, row in enumerate(rows):
                m = metrics_message(sensor, i, r)
                self.assertEqual(float(row["t_s"]), m.header.stamp.to_sec())
                self.assertEqual(float(row["kb_f_max"]), m.kb_f_max)
                self.assertEqual(float(row["ppv_vertical_m_s"]), m.ppv_vertical_m_s)
                self.assertEqual(row["verdict"], "not applicable" if i == 0 else "OK")
                self.assertEqual([float(row[f"L_{c:g}Hz_db"]) for c in BANDS_HZ], list(m.third_octave_level_db))
        with open(self.out / "csv" / "third_octave_levels.csv") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), len(SENSORS) * len(BANDS_HZ))
        floor = [r for r in rows if r["sensor"] == SENSORS[1]]
        self.assertEqual([r["kind"] for r in floor], ["floor"] * len(BANDS_HZ))
        self.assertEqual([float(r["level_db"]) for r in floor], list(metrics_message(SENSORS[1], 1, 1).third_octave_level_db))
        import scipy.io
        mat = scipy.io.loadmat(str(self.out / "railvib.mat"), squeeze_me=True, struct_as_record=False)
        ground = getattr(mat["metrics"], SENSORS[0])
        self.assertEqual(list(ground.kb_f), [0.01, 0.02])
        self.assertEqual(ground.third_octave_level_db.shape, (2, len(BANDS_HZ)))
        self.assertEqual(list(ground.third_octave_center_hz), BANDS_HZ)
        self.assertEqual(list(ground.verdict), ["not applicable"] * 2)

    def test_the_surface_series_is_compressed_vtk_with_three_components_at_the_snapshot_times(self):
        import meshio
        pvd = ET.parse(self.out / "vtk" / "surface.pvd").getroot()
        self.assertEqual(pvd.get("type"), "Collection")
        sets = pvd.find("Collection").findall("DataSet")
        self.assertEqual([float(d.get("timestep")) for d in sets], [0.1, 0.2, 0.3])
        for s, d in enumerate(sets):
            path = self.out / "vtk" / d.get("file")
            head = path.read_bytes()[:400].decode("latin-1")
            self.assertIn('type="UnstructuredGrid"', head)
            self.assertIn("vtkZLibDataCompressor", head)  # binary and compressed, not ASCII
            grid = meshio.read(str(path))
            self.assertEqual(grid.points.shape, (20, 3))
            self.assertEqual(grid.cells_dict["quad"].shape, (4 * 3, 4))
            # Point (i, j) = (3, 2) is the message's value [3 + 5 x 2] (x fastest), at (-2 + 1.5, 1 + 0.5, 0).
            p = 3 + 5 * 2
            self.assertEqual(list(grid.points[p]), [-0.5, 1.5, 0.0])
            vz = SNAP_SCALE * (s + 3 + 10 * 2)
            np.testing.assert_allclose(grid.point_data["velocity_m_s"][p], [-2.0 * vz, 3.0 * vz, vz], rtol=1e-6)
            self.assertNotIn("vertical_velocity_m_s", grid.point_data)  # velocity_m_s's Z, not written twice
            # Every quad is a cell of the grid: its corners one spacing apart, counter-clockwise seen from z up.
            for quad in grid.cells_dict["quad"]:
                c = grid.points[quad]
                np.testing.assert_allclose(c[1] - c[0], [0.5, 0.0, 0.0])
                np.testing.assert_allclose(c[3] - c[0], [0.0, 0.25, 0.0])
                np.testing.assert_allclose(c[2] - c[0], [0.5, 0.25, 0.0])

    def test_the_section_series_is_a_grid_with_z_up_and_the_vertical_alone_when_recorded_so(self):
        import meshio
        sets = ET.parse(self.out / "vtk" / "section.pvd").getroot().find("Collection").findall("DataSet")
        self.assertEqual(len(sets), 3)
        grid = meshio.read(str(self.out / "vtk" / sets[2].get("file")))
        # Point (j = 1, row r = 2): y = -3 + 1.5, z = -1.5 (depth 1.5 m), value SNAP_SCALE x (2 + 1 + 200).
        p = 1 + 3 * 2
        self.assertEqual(list(grid.points[p]), [0.0, -1.5, -1.5])
        self.assertAlmostEqual(float(grid.point_data["vertical_velocity_m_s"][p]), SNAP_SCALE * (2 + 1 + 200),
                               delta=1e-6 * SNAP_SCALE * 203)
        # The test bag's sections carry the vertical only (snapshot_components: vertical).
        self.assertNotIn("velocity_m_s", grid.point_data)
        self.assertIn("vertical_velocity_m_s only", self.result.stdout)

    def test_a_foreign_bag_is_refused(self):
        foreign = WORK / "foreign.bag"
        with rosbag.Bag(str(foreign), "w") as bag:
            bag.write("/chatter", String(data="hi"), rospy.Time(1))
        out = run_script("export.py", foreign, WORK / "foreign_out")
        self.assertEqual(out.returncode, 2)
        self.assertIn("not a railvib bag", out.stderr)
        self.assertNotIn("Traceback", out.stderr)


class MetricsBands(unittest.TestCase):
    def test_bands_that_change_during_the_record_are_said_and_only_the_last_levels_kept(self):
        def changing(sensor, i, r):
            m = metrics_message(sensor, i, r)
            if i == 0 and r == 1:
                m.third_octave_center_hz, m.third_octave_level_db = [10.0, 12.5], [70.0, 71.0]
            return m
        bag = export_bag(WORK / "bands.bag", metrics_of=changing)
        out = run_script("export.py", bag, WORK / "bands_out", "--what", "csv,mat")
        self.assertEqual(out.returncode, 0, out.stderr + out.stdout)
        self.assertIn("metrics of ground_2m: the bands change during the record", out.stderr + out.stdout)
        with open(WORK / "bands_out" / "csv" / "metrics_ground_2m.csv") as f:
            header = next(csv.reader(f))
        self.assertFalse([h for h in header if h.startswith("L_")], header)
        with open(WORK / "bands_out" / "csv" / "third_octave_levels.csv") as f:
            ground = [r for r in csv.DictReader(f) if r["sensor"] == "ground_2m"]
        self.assertEqual([(float(r["center_hz"]), float(r["level_db"])) for r in ground], [(10.0, 70.0), (12.5, 71.0)])
        import scipy.io
        mat = scipy.io.loadmat(str(WORK / "bands_out" / "railvib.mat"), squeeze_me=True, struct_as_record=False)
        self.assertEqual(list(getattr(mat["metrics"], "ground_2m").third_octave_level_db), [70.0, 71.0])


class SensorTopics(unittest.TestCase):
    def test_a_lost_per_sensor_message_is_a_finding(self):
        whole = bag_check.check_bag(export_bag(WORK / "whole.bag"))
        self.assertEqual(whole.code, 0, whole.findings)
        lossy = bag_check.check_bag(export_bag(WORK / "lossy.bag", drop_one=True))
        self.assertEqual(lossy.code, 1)
        self.assertTrue(any("/sensors/house_first_floor/velocity: 599 messages for the 600 samples" in f
                            for f in lossy.findings), lossy.findings)

    def test_a_per_sensor_topic_of_another_type_is_refused(self):
        path = WORK / "wrongtype.bag"
        shutil.copy(export_bag(WORK / "base.bag", per_sensor_messages=False), path)
        with rosbag.Bag(str(path), "a") as bag:
            bag.write(names.sensor_topic("ground_2m", "velocity"), String(data="x"), rospy.Time(1))
        r = bag_check.check_bag(path)
        self.assertIn("geometry_msgs/Vector3Stamped", r.refused or "")


FAKE_RUNNER = '''#!/usr/bin/env python3
# Stands in for ./railvib run: records its arguments and writes a bag of sensor metrics that
# depend on them (PPV = speed x 1e-4 m/s; KB_Fmax = 1000 x defect height from its config file;
# one-third octave levels of an amplitude proportional to the defect height, with a trench in
# soil.inclusions lowering the bands from 20 Hz by 10 dB at the far sensor).
import json, sys, pathlib, yaml, rosbag, rospy
import railvib.msg as rm
args = dict(a.split(":=", 1) for a in sys.argv[2:])
pathlib.Path(args["bag"]).with_name("argv.json").write_text(json.dumps(sys.argv[1:]))
config = yaml.safe_load(open(args["config"]))
height = config.get("unevenness", {}).get("defect", {}).get("height_m", 1.0e-3)
speed = float(args.get("speed", "8.33"))
if speed == 99:
    sys.exit(1)
with rosbag.Bag(args["bag"], "w") as bag:
    for name, scale in (("ground_2m", 1.0), ("ground_8m", 0.25)):
        m = rm.VibrationMetrics()
        m.header.stamp = rospy.Time(1)
        m.sensor_name = name
        m.ppv_m_s = speed * 1e-4 * scale
        m.governing_ppv_m_s = m.ppv_m_s
        m.governing_component = 2
        m.dominant_frequency_hz = 30.0
        m.din4150_3_limit_m_s = 0.01
        m.kb_f_max = 1000 * height * scale
        m.din4150_2_verdict = 1 if m.kb_f_max > 0.6 else 0
        trench = bool(config.get("soil", {}).get("inclusions"))
        m.third_octave_center_hz = [10.0, 12.5, 16.0, 20.0, 25.0, 31.5]
        m.resolved_hz = 30.0 if name == "ground_8m" else 0.0  # a model resolving 30 Hz there; 0: no limit
        m.third_octave_level_db = [20 * __import__("math").log10(height * scale * 1e9) + 3 * q
                                   - (10.0 if trench and name == "ground_8m" and f >= 20.0 else 0.0)
                                   for q, f in enumerate(m.third_octave_center_hz)]
        bag.write("/sensor_metrics", m, rospy.Time(1))
'''

CATALOGUE = '''measures:
  defect_half:
    description: a smaller defect
    set: {unevenness.defect.height_m: 0.5e-3}
  trench:
    description: an open trench
    set:
      soil.inclusions: [{name: trench, kind: void, x_m: [-14.8, 14.8], y_m: [3.1, 3.9], depth_m: [0.0, 4.0e0]}]
  bad_key:
    description: a key no loader knows
    set: {track.railpad.stiffnes_n_m: 3.0e7}
'''


class Study(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.runner = WORK / "fake_run.py"
        cls.runner.write_text(FAKE_RUNNER)

    def study(self, out, *args):
        return run_script("study.py", "--runner", f"{sys.executable} {self.runner}", "--outdir", out, *args)

    def test_a_grid_runs_every_combination_and_tabulates_the_recorded_metrics(self):
        out = WORK / "grid"
        r = self.study(out, "--vary", "speed=5,10", "--vary", "unevenness.defect.height_m=0.5e-3,2e-3",
                       "--arg", "duration:=3.0", "--jobs", "2")
        self.assertEqual(r.returncode, 0, r.stderr + r.stdout)
        self.assertIn("[4/4]", r.stdout)
        self.assertIn("ETA", r.stdout)
        with open(out / "study.csv") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 4 * 2)  # 4 runs x 2 sensors
        seen = set()
        for row in rows:
            speed, height = float(row["speed"]), float(row["unevenness.defect.height_m"])
            seen.add((speed, height))
            scale = 1.0 if row["sensor"] == "ground_2m" else 0.25
            self.assertAlmostEqual(float(row["ppv_mm_s"]), speed * 0.1 * scale, places=12)
            self.assertAlmostEqual(float(row["kb_f_max"]), 1000 * height * scale, places=12)
            self.assertEqual(row["status"], "ok")
        self.assertEqual(seen, {(5.0, 5e-4), (5.0, 2e-3), (10.0, 5e-4), (10.0, 2e-3)})
        # Each run: its launch arguments, and a config file with its dotted keys over the base.
        for run_dir in sorted(out.glob("run_*")):
            argv = json.loads((run_dir / "argv.json").read_text())
            self.assertEqual(argv[0], "haren")
            self.assertIn("duration:=3.0", argv)
            config = yaml.safe_load((run_dir / "config.yaml").read_text())
            self.assertEqual(config["include"], [str(ROOT / "config" / "haren.yaml")])
            self.assertIn(config["unevenness"]["defect"]["height_m"], (5e-4, 2e-3))
        md = (out / "study.md").read_text()
        self.assertIn("| speed | unevenness.defect.height_m |", md)
        for figure in ("study_speed.png", "study_unevenness_defect_height_m.png"):
            self.assertGreater((out / figure).stat().st_size, 10000)

    def test_a_failed_run_fails_the_study_and_is_named(self):
        out = WORK / "failed"
        r = self.study(out, "--vary", "speed=5,99")
        self.assertEqual(r.returncode, 1)
        self.assertIn("1 run(s) failed: speed=99", r.stdout)
        with open(out / "study.csv") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual([row["status"] for row in rows if row["speed"] == "99"], ["failed"])

    def test_mitigate_runs_the_baseline_and_each_measure_and_gives_the_insertion_loss(self):
        catalogue = WORK / "catalogue.yaml"
        catalogue.write_text(CATALOGUE)
        out = WORK / "mitigate"
        r = self.study(out, "--catalogue", catalogue, "--measure", "defect_half", "--measure", "trench")
        self.assertEqual(r.returncode, 0, r.stderr + r.stdout)
        self.assertIn("[3/3]", r.stdout)
        # The trench's list of inclusions reaches its run's config file as a list, and 4.0e0 as the number
        # yaml-cpp reads (YAML 1.1 makes it a word, which --set would pass on quoted).
        config = yaml.safe_load((out / "run_003" / "config.yaml").read_text())
        self.assertEqual(config["soil"]["inclusions"][0]["depth_m"], [0.0, 4.0])
        with open(out / "mitigation.csv") as f:
            bands = list(csv.DictReader(f))
        self.assertEqual(len(bands), 2 * 2 * 6)  # 2 measures x 2 sensors x 6 bands
        for b in bands:
            il = float(b["il_db"])
            if b["measure"] == "defect_half":  # half the amplitude everywhere: 20 log10 2
                self.assertAlmostEqual(il, 20 * math.log10(2.0), places=9)
            else:  # the trench: 10 dB from 20 Hz at the far sensor, nothing elsewhere
                far = b["sensor"] == "ground_8m" and float(b["band_hz"]) >= 20.0
                self.assertAlmostEqual(il, 10.0 if far else 0.0, places=9)
        with open(out / "mitigation_summary.csv") as f:
            summary = {(row["measure"], row["sensor"]): row for row in csv.DictReader(f)}
        half = summary[("defect_half", "ground_2m")]
        self.assertAlmostEqual(float(half["overall_il_db"]), 20 * math.log10(2.0), places=9)
        self.assertAlmostEqual(float(half["kb_f_max_with"]) / float(half["kb_f_max_base"]), 0.5, places=12)
        self.assertEqual((half["din4150_2_base"], half["din4150_2_with"]), ("WARN", "OK"))
        # Overall IL of the trench at the far sensor: the energy sum of bands 3 dB apart, the top ones 10 dB
        # lower, over the bands the model resolves there (up to 30 Hz: the 31.5 Hz band left out).
        levels = [3.0 * q for q in range(5)]
        e = lambda ls: 10 * math.log10(sum(10 ** (v / 10) for v in ls))  # noqa: E731
        self.assertAlmostEqual(float(summary[("trench", "ground_8m")]["overall_il_db"]),
                               e(levels) - e(levels[:3] + [v - 10 for v in levels[3:]]), places=9)
        self.assertEqual(float(summary[("trench", "ground_8m")]["resolved_hz"]), 30.0)
        self.assertIn("up to the model's resolved frequency (30 Hz", (out / "mitigation.md").read_text())
        md = (out / "mitigation.md").read_text()
        self.assertIn("- ground_2m, DIN 4150-2 (WARN without): defect_half", md)
        self.assertGreater((out / "mitigation.png").stat().st_size, 10000)

    def test_mitigate_refuses_unknown_measures_and_bad_keys_before_any_run(self):
        catalogue = WORK / "catalogue.yaml"
        catalogue.write_text(CATALOGUE)
        for measure, message in (("grinding", "unknown measure 'grinding'"),
                                 ("bad_key", "track.railpad.stiffnes_n_m")):
            out = WORK / "mitigate_refused"
            r = self.study(out, "--catalogue", catalogue, "--measure", measure)
            self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
            self.assertIn(message, r.stderr)
            self.assertFalse(list(out.glob("run_*")), measure)

    def test_a_key_into_a_list_varies_that_entry_alone(self):
        # The layered soil's top layer stiffer and softer; the other four layers and every other key as
        # the base has them (the loader's merged configuration, railvib_tool config-check --dump).
        tool = find_railvib_tool()
        self.assertTrue(tool, "railvib_tool not built")

        def merged(config):
            r = subprocess.run([tool, "config-check", "--config", str(config), "--dump"], capture_output=True,
                               text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
            return railvib_yaml.load(r.stdout)  # numbers as yaml-cpp reads them (84.0e6 too)

        base = merged(ROOT / "config" / "haren.yaml")
        out = WORK / "layers"
        key = "soil.layers[0].young_modulus_pa"
        r = self.study(out, "--vary", f"{key}=40e6,80e6", "--set", "unevenness.defect.height_m=0.5e-3")
        self.assertEqual(r.returncode, 0, r.stderr + r.stdout)
        seen = []
        for run_dir in sorted(out.glob("run_*")):
            run = merged(run_dir / "config.yaml")
            seen.append(run["soil"]["layers"][0]["young_modulus_pa"])
            expected = copy.deepcopy(base)
            expected["soil"]["layers"][0]["young_modulus_pa"] = seen[-1]
            expected["unevenness"]["defect"]["height_m"] = 0.5e-3
            self.assertEqual(run, expected, run_dir)
        self.assertEqual(seen, [40e6, 80e6])
        with open(out / "study.csv") as f:
            self.assertEqual(sorted({float(row[key]) for row in csv.DictReader(f)}), [40e6, 80e6])

    def test_bad_keys_and_values_are_refused_before_any_run(self):
        for args, message in ((["--vary", "sped=1,2"], "neither a launch argument"),
                              (["--set", "soil..mesh=1"], "dotted words"),
                              (["--set", "soil.layers[0]x.thickness_m=1"], "a list entry by its index"),
                              (["--vary", "soil.layers[9].thickness_m=1,2"], "soil.layers has 5 entries"),
                              # a value a loader refuses, in the second run: no run starts
                              (["--vary", "soil.rayleigh_beta_s=4e-4,-1"], "soil.rayleigh_beta_s = -1"),
                              # a launch argument as the nodes map it
                              (["--vary", "speed=5,-1"], "simulation.speed_m_s = -1"),
                              (["--set", "simulation.speed_m_s=[1, 2]"], "one plain value"),
                              (["--vary", "speed="], "KEY=V1,V2")):
            out = WORK / "refused"
            r = self.study(out, *args)
            self.assertEqual(r.returncode, 2, args)
            self.assertIn(message, r.stderr, args)
            self.assertFalse(list(out.glob("run_*")), args)


class MeasuredImport(unittest.TestCase):
    RATE = 2000.0

    def importing(self, record, *args):
        r = run_script("measured_record.py", record, *args)
        self.assertNotIn("Traceback", r.stderr)
        return r

    def metrics(self, record, *args):
        r = self.importing(record, *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        return json.loads(r.stdout)

    def sine_csv(self, name, f_hz, amplitude, header="t_s,ax,ay", seconds=8.0, phase=0.4):
        t = np.arange(0.0, seconds, 1.0 / self.RATE)
        x = amplitude * np.sin(2 * np.pi * f_hz * t + phase)
        path = WORK / name
        np.savetxt(path, np.c_[t, x, 0.5 * x], delimiter=",", header=header, comments="", fmt="%.12g")
        return path

    def test_an_acceleration_sine_gives_its_velocity_amplitude_as_ppv(self):
        amplitude_g, f_hz = 0.05, 20.0
        expected_mm_s = amplitude_g * 9.80665 / (2 * np.pi * f_hz) * 1e3
        csv_path = self.sine_csv("acc_g.csv", f_hz, amplitude_g)
        m = self.metrics(csv_path, "--unit", "g", "--out", WORK / "acc_g_velocity.csv")
        ppv = {c["column"]: c["ppv_mm_s"] for c in m["din4150_3"]["components"]}
        self.assertAlmostEqual(ppv["ax"] / expected_mm_s, 1.0, delta=0.01)
        self.assertAlmostEqual(ppv["ay"] / (0.5 * expected_mm_s), 1.0, delta=0.01)
        v = np.loadtxt(WORK / "acc_g_velocity.csv", delimiter=",", skiprows=1)
        self.assertAlmostEqual(np.abs(v[:, 1]).max() * 1e3 / expected_mm_s, 1.0, delta=0.001)
        self.assertAlmostEqual(v[1, 0], 1.0 / self.RATE, places=12)
        provenance = json.loads((WORK / "acc_g_velocity.json").read_text())
        self.assertEqual((provenance["quantity"], provenance["unit"], provenance["channels"]),
                         ("acceleration", "g", ["ax", "ay"]))
        # The same record as a 16-bit WAV whose full scale is 0.1 g.
        from scipy.io import wavfile
        t = np.arange(0.0, 8.0, 1.0 / self.RATE)
        x = amplitude_g * np.sin(2 * np.pi * f_hz * t + 0.4)
        wavfile.write(WORK / "acc.wav", int(self.RATE), np.round(x / 0.1 * 32768).clip(-32768, 32767).astype(np.int16))
        m = self.metrics(WORK / "acc.wav", "--unit", "g", "--sensitivity", "0.1", "--out", WORK / "acc_wav.csv")
        self.assertAlmostEqual(m["din4150_3"]["components"][0]["ppv_mm_s"] / expected_mm_s, 1.0, delta=0.01)
        self.assertEqual(m["din4150_3"]["components"][0]["column"], "ch0")

    def test_the_din_45669_test_vectors_pass_on_imported_acceleration(self):
        # DIN 45669-1: a continuous sine of 1 mm/s; KB_Fmax per frequency (railvib_tool din-check's table).
        for f_hz, kb_fmax in ((5.6, 0.528), (16.0, 0.680), (31.5, 0.700), (80.0, 0.597)):
            t = np.arange(0.0, 10.0, 1.0 / self.RATE)
            a = 2 * np.pi * f_hz * 1e-3 * np.cos(2 * np.pi * f_hz * t)
            path = WORK / f"din_{f_hz}.csv"
            np.savetxt(path, np.c_[t, a * 1e3], delimiter=",", header="time,az", comments="", fmt="%.12g")
            m = self.metrics(path, "--unit", "mm_s2", "--out", WORK / f"din_{f_hz}_v.csv")
            self.assertAlmostEqual(m["din4150_2"]["kb_fmax"] / kb_fmax, 1.0, delta=0.01, msg=f"{f_hz} Hz")
        # A velocity record in mm/s is taken as it is (only the mean removed).
        path = self.sine_csv("vel_mm_s.csv", 16.0, 1.0, header="t,vz,vy")
        m = self.metrics(path, "--quantity", "velocity", "--unit", "mm_s", "--out", WORK / "vel_v.csv")
        self.assertAlmostEqual(m["din4150_3"]["components"][0]["ppv_mm_s"], 1.0, delta=0.001)

    def test_bad_records_and_options_are_refused_with_the_reason(self):
        good = self.sine_csv("good.csv", 20.0, 0.1)
        (WORK / "garbage.wav").write_bytes(b"this is no wav at all, just text")
        uneven = WORK / "uneven.csv"
        uneven.write_text("t_s,az\n" + "".join(f"{t},{0.1}\n" for t in [0, 0.001, 0.002, 0.0035, 0.0045]
                                                  + [0.005 + 0.001 * i for i in range(2000)]))
        short = self.sine_csv("short.csv", 20.0, 0.1, seconds=0.5)
        huge = self.sine_csv("huge.csv", 20.0, 2.0e5)
        cases = [
            ((WORK / "garbage.wav", "--sensitivity", "1"), "not a WAV file"),
            ((WORK / "acc.wav.missing",), "not found"),
            ((WORK,), "not a regular file"),
            ((good, "--channels", "az"), "no channel 'az' (columns: t_s, ax, ay)"),
            ((good, "--time-column", "tt"), "no time column 'tt'"),
            ((good, "--rate", "1000"), "--rate given and a time column"),
            ((good, "--unit", "mm_s"), "--unit mm_s: for acceleration one of m_s2, mm_s2, g"),
            ((good, "--sensitivity", "2"), "--sensitivity is for WAV records"),
            ((good, "--highpass-hz", "900"), "--highpass-hz 900.0"),
            ((good, "--highpass-hz", "nan"), "not a finite number"),
            ((uneven,), "differs from the mean step"),
            ((short,), "too short for a metric"),
            ((huge,), "beyond the 100000 m/s^2"),
            ((good, "--out", WORK), "is a directory"),
        ]
        for args, message in cases:
            r = self.importing(*args, "--no-metrics")
            self.assertEqual(r.returncode, 2, (args, r.stderr))
            self.assertIn(message, r.stderr, args)


class MeasuredReport(unittest.TestCase):
    """./railvib report of a measured record alone: an imported 20 Hz acceleration sine gives its
    velocity amplitude as PPV (1 %), and the standards judged follow --kind (DIN 4150-3's foundation
    curve at 20 Hz, its floor value, none in the free field)."""

    @classmethod
    def setUpClass(cls):
        rate, f_hz, cls.amplitude_m_s2 = 2000.0, 20.0, 0.5
        t = np.arange(0.0, 8.0, 1.0 / rate)
        a = cls.amplitude_m_s2 * np.sin(2 * np.pi * f_hz * t + 0.4)
        np.savetxt(WORK / "floor_acc.csv", np.c_[t, a], delimiter=",", header="t_s,az", comments="", fmt="%.12g")
        r = run_script("measured_record.py", WORK / "floor_acc.csv", "--out", WORK / "floor_velocity.csv",
                       "--no-metrics")
        assert r.returncode == 0, r.stderr
        cls.expected_mm_s = cls.amplitude_m_s2 / (2 * np.pi * f_hz) * 1e3

    def report(self, out, *args):
        r = run_script("report.py", WORK / "floor_velocity.csv", WORK / out, *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        return json.loads((WORK / out / "report.json").read_text())

    def test_the_record_alone_gives_its_ppv_and_the_standards_of_where_it_was_measured(self):
        found = self.report("rep_foundation", "--kind", "foundation")
        d3 = found["metrics"]["din4150_3"]
        vz = d3["components"][2]
        self.assertEqual(found["axes"], ["-", "-", "az"])  # one channel: the vertical
        self.assertAlmostEqual(vz["ppv_mm_s"] / self.expected_mm_s, 1.0, delta=0.01)
        self.assertAlmostEqual(vz["dominant_frequency_hz"], 20.0, delta=0.5)
        # DIN 4150-3 Table 1 row 2 at the foundation: 5 + (f - 10) / 40 x 10 mm/s between 10 and 50 Hz.
        self.assertAlmostEqual(vz["din4150_3_limit_mm_s"], 7.5, delta=0.15)
        self.assertEqual(found["standards"]["floor_velocity"]["guideline"], "foundation curve")
        floor = self.report("rep_floor", "--kind", "floor")
        self.assertAlmostEqual(floor["metrics"]["din4150_3"]["components"][2]["din4150_3_limit_mm_s"], 20.0)
        free = self.report("rep_free", "--kind", "free_field")
        self.assertEqual(free["metrics"]["sensor"]["verdict"], "not applicable")
        for out in ("rep_foundation", "rep_floor", "rep_free"):
            for png in ("sensors.png", "standards.png"):
                self.assertGreater((WORK / out / png).stat().st_size, 10000)
        text = (WORK / "rep_foundation" / "report.md").read_text()
        self.assertIn("floor_acc.csv", text)  # the provenance of ./railvib import

    def test_bad_options_are_refused(self):
        for args, message in ((("--kind", "attic"), "--kind attic"), (("--axes", "az"), "three names"),
                              (("--period", "evening"), "--period evening")):
            r = run_script("report.py", WORK / "floor_velocity.csv", WORK / "rep_bad", *args)
            self.assertEqual(r.returncode, 1, (args, r.stderr))  # report's refusal
            self.assertIn(message, r.stderr)
            self.assertNotIn("Traceback", r.stderr)


CLASSES = (Export, MetricsBands, SensorTopics, Study, MeasuredImport, MeasuredReport)


if __name__ == "__main__":
    suite = unittest.TestSuite()
    for cls in CLASSES:
        suite.addTests(unittest.defaultTestLoader.loadTestsFromTestCase(cls))
    result = run_verbose(suite)
    if len(sys.argv) > 1:
        write_junit(result, "export_tests", CLASSES, sys.argv[1])
    shutil.rmtree(WORK, ignore_errors=True)
    sys.exit(0 if result.wasSuccessful() else 1)
