#!/usr/bin/env python3
"""railvib bag check: is this a railvib bag, and is every stream it should hold there, whole?

usage: bag_check.py BAG        (prints one line per finding; `./railvib report` runs it first)

Exit codes:
  0  a railvib bag with every expected stream complete (contiguous from sample 0,
     the last block flagged end_of_stream), every block well formed and every
     value finite;
  1  a railvib bag, readable, but not whole: a stream missing (it sent no
     block), stopped early or with non-finite values, or the recorder stopped
     on an error (disk full, a gap, ...); the findings name each stream;
  2  refused: not a readable bag, not a railvib bag (no railvib stream and no
     recording status), a railvib topic name with another message type, a
     malformed block (array sizes that do not match its counts), or a recorded
     metrics, snapshot or transform message that breaks the message contract
     (scripts/railvib_contracts.py: a NaN, a sensor the run does not have, a
     grid its values do not fill, a rotation that is not one).

The expected streams are those the recorder was told to record, from the
status it writes into the bag when it closes it (/railvib/recording). A bag
without it (recorded by an older recorder, or whose recorder was killed) is
checked for the railvib streams of its scenario: contact forces and soil loads
(track scenario), plus the soil velocities, building response (when the house's
layout is there) and sensor samples (Haren scenario).
"""
import json
import math
import sys

import numpy as np

import railvib_contracts
import railvib_names as names
import railvib_yaml

try:
    import rosbag
    import yaml
except ImportError:  # pragma: no cover
    sys.exit("railvib bag check: python3-rosbag and python3-yaml are required (./railvib setup installs them)")

TYPES = {
    names.CONTACT_FORCES: "railvib/ContactForces",
    names.SOIL_LOADS: "railvib/SoilLoads",
    names.SURFACE_VELOCITIES: "railvib/SurfaceVelocities",
    names.BUILDING_RESPONSE: "railvib/BuildingResponse",
    names.SENSOR_SAMPLES: "railvib/SensorSamples",
    names.SLEEPER_LAYOUT: "railvib/SleeperLayout",
    names.SURFACE_POINTS: "railvib/PointLayout",
    names.BUILDING_POINTS: "railvib/PointLayout",
    names.SURFACE_SNAPSHOT: "railvib/SurfaceSnapshot",
    names.SECTION_SNAPSHOT: "railvib/SectionSnapshot",
    names.SENSOR_METRICS: "railvib/VibrationMetrics",
    names.RECORDING_STATUS: "std_msgs/String",
    names.SCENARIO: "std_msgs/String",
    names.DIAGNOSTICS: "diagnostic_msgs/DiagnosticArray",
    "/tf": "tf2_msgs/TFMessage",
    "/tf_static": "tf2_msgs/TFMessage",
}
# Per stream: its point count field and its arrays (name, values per point: a number, or the block's
# field that says it, e.g. a full-width track's rail seats per sleeper).
ARRAYS = {
    names.CONTACT_FORCES: ("wheel_count", [("position_m", 1), ("force_n", 1), ("unevenness_m", 1)]),
    names.SOIL_LOADS: ("sleeper_count", [("force_n", "seats_per_sleeper")]),
    names.SURFACE_VELOCITIES: ("receiver_count", [("velocity_m_s", 3)]),
    names.BUILDING_RESPONSE: ("point_count", [("velocity_m_s", 3)]),
    names.SENSOR_SAMPLES: ("sensor_count", [("velocity_m_s", 3), ("acceleration_m_s2", 3)]),
}
# The standard-typed per-sensor topics (/sensors/<name>/<what>).
SENSOR_TOPIC_TYPES = {"imu": "sensor_msgs/Imu", "velocity": "geometry_msgs/Vector3Stamped",
                      "metrics": "railvib/VibrationMetrics"}
LAYOUT_OF = {names.SOIL_LOADS: names.SLEEPER_LAYOUT, names.SURFACE_VELOCITIES: names.SURFACE_POINTS,
             names.BUILDING_RESPONSE: names.BUILDING_POINTS}


class Result:
    def __init__(self, path):
        self.path = path
        self.refused = None       # why the bag is refused (exit 2)
        self.findings = []        # why it is not whole (exit 1)
        self.incomplete = []      # expected streams missing or stopped early
        self.expected = []
        self.recording = None     # the recorder's status, if recorded
        self.notes = []           # information, not findings

    @property
    def code(self):
        return 2 if self.refused else (1 if self.findings or self.incomplete else 0)


def _finite(values):
    return bool(np.isfinite(np.asarray(values, dtype=float)).all())


def _check_stream(bag, topic, result):
    """Contiguity, end flag, block shapes and values of one stream topic."""
    count_field, arrays = ARRAYS[topic]
    expected_index = 0
    period = None
    last = None
    blocks = 0
    for _, m, _ in bag.read_messages(topics=[topic]):
        blocks += 1
        if m.first_sample_index != expected_index:
            result.findings.append(f"{topic}: samples {expected_index}..{m.first_sample_index - 1} missing "
                                   f"(block at sample {m.first_sample_index})")
            result.incomplete.append(topic)
            return
        if last is not None and last.end_of_stream:
            result.findings.append(f"{topic}: a block after the end_of_stream block (sample {m.first_sample_index})")
        if not (m.sample_period_s > 0 and math.isfinite(m.sample_period_s)) or (
                period is not None and abs(m.sample_period_s - period) > 1e-9 * period):
            result.refused = (f"{topic}: block at sample {m.first_sample_index} has sample_period_s = "
                              f"{m.sample_period_s}" + (f", not {period}" if period else ""))
            return
        period = m.sample_period_s
        points = getattr(m, count_field)
        if points < 1 or (last is not None and points != getattr(last, count_field)):
            result.refused = (f"{topic}: block at sample {m.first_sample_index} has {count_field} = {points}"
                              + (f", not {getattr(last, count_field)} as before" if last is not None else
                                 ", not at least 1"))
            return
        listed = getattr(m, "sensor_names", None)
        if listed is not None and len(listed) != points:
            result.refused = (f"{topic}: block at sample {m.first_sample_index} names {len(listed)} sensors for "
                              f"{count_field} = {points}")
            return
        for field, per_point_spec in arrays:
            values = getattr(m, field)
            per_point = getattr(m, per_point_spec) if isinstance(per_point_spec, str) else per_point_spec
            if isinstance(per_point_spec, str) and per_point not in (1, 2):
                result.refused = (f"{topic}: block at sample {m.first_sample_index}: {per_point_spec} = {per_point}, "
                                  "not 1 (one force per sleeper) or 2 (a force per rail seat)")
                return
            if len(values) != m.sample_count * points * per_point:
                result.refused = (f"{topic}: block at sample {m.first_sample_index}: {field} has {len(values)} values, "
                                  f"not sample_count x {count_field} x {per_point} = "
                                  f"{m.sample_count} x {points} x {per_point}")
                return
            if not _finite(values):
                bad = next(i for i, v in enumerate(values) if not math.isfinite(v))
                result.findings.append(f"{topic}: {field}[{bad}] = {values[bad]} in the block at sample "
                                       f"{m.first_sample_index}: not finite")
        expected_index += m.sample_count
        last = m
    if blocks == 0:
        result.findings.append(f"{topic}: no block recorded (the stream never started)")
        result.incomplete.append(topic)
    elif expected_index == 0:
        result.findings.append(f"{topic}: {blocks} block(s) without a sample")
        result.incomplete.append(topic)
    elif not last.end_of_stream:
        result.findings.append(f"{topic}: stops at sample {expected_index} without its end_of_stream block")
        result.incomplete.append(topic)


def check_bag(path):
    """The findings on one bag (see the module comment); never raises for a bad bag."""
    result = Result(str(path))
    try:
        bag = rosbag.Bag(str(path))
    except Exception as e:  # rosbag raises several types for truncated, unindexed or foreign files
        result.refused = f"cannot read {path} as a bag: {e}"
        return result
    with bag:
        info = bag.get_type_and_topic_info().topics
        for topic, t in info.items():
            expected_type = TYPES.get(topic) or sensor_topic_type(topic)
            if expected_type and t.msg_type != expected_type:
                result.refused = (f"{topic} has type {t.msg_type}, railvib's is {expected_type}: not a railvib bag, "
                                  f"or recorded by something else under railvib's names")
                return result
        if names.RECORDING_STATUS in info:
            for _, m, _ in bag.read_messages(topics=[names.RECORDING_STATUS]):
                try:
                    result.recording = json.loads(m.data)
                except ValueError:
                    result.refused = f"{names.RECORDING_STATUS}: not the recorder's JSON status"
                    return result
            result.expected = list(result.recording.get("expected_streams", []))
            status = str(result.recording.get("status", ""))
            if not status.startswith("closed"):
                result.findings.append(f"the recorder stopped: {status}")
        else:
            present = [s for s in names.STREAMS if s in info]
            if not present:
                listed = ", ".join(sorted(info)) or "none"
                result.refused = f"not a railvib bag: none of its topics ({listed}) is a railvib stream"
                return result
            result.expected = [names.CONTACT_FORCES, names.SOIL_LOADS]
            if names.SURFACE_POINTS in info or names.SURFACE_VELOCITIES in info:
                result.expected += [names.SURFACE_VELOCITIES, names.SENSOR_SAMPLES]
                if names.BUILDING_POINTS in info:
                    result.expected.insert(3, names.BUILDING_RESPONSE)
            result.notes.append(f"no {names.RECORDING_STATUS} in the bag (an older recorder, or it was killed): "
                                f"checking {', '.join(result.expected)}")
        unknown = [s for s in result.expected if s not in ARRAYS]
        if unknown:
            result.refused = f"the recording status expects streams railvib does not have: {', '.join(unknown)}"
            return result
        for topic in result.expected:
            if topic not in info:
                result.findings.append(f"{topic}: no block recorded (the stream never started)")
                result.incomplete.append(topic)
                continue
            _check_stream(bag, topic, result)
            if result.refused:
                return result
            layout = LAYOUT_OF.get(topic)
            if layout and layout not in info:
                result.findings.append(f"{topic}: its layout {layout} is not in the bag")
        if names.SENSOR_SAMPLES in result.expected and names.SENSOR_SAMPLES in info and names.SENSOR_METRICS not in info:
            result.findings.append(f"{names.SENSOR_METRICS}: no metrics recorded for the sensors")
        _check_sensor_topics(bag, info, result)
        _check_messages(bag, info, result)
    return result


def scenario_record(bag):
    """The scenario record (/railvib/scenario) as a dict, and why it is not there or not readable."""
    for _, m, _ in bag.read_messages(topics=[names.SCENARIO]):
        text = getattr(m, "data", None)
        if not isinstance(text, str):
            return None, f"{names.SCENARIO} is not a std_msgs/String"
        try:
            record = railvib_yaml.load(text)
        except yaml.YAMLError as e:
            return None, f"{names.SCENARIO} is not readable YAML ({str(e).splitlines()[0]})"
        if not isinstance(record, dict):
            return None, f"{names.SCENARIO} is not a YAML mapping"
        return record, None
    return None, "not recorded (bag from an older railvib)"


def _recorded_velocity_limit(bag):
    """limits.velocity_m_s of the recorded scenario (/railvib/scenario), else the default."""
    record, _ = scenario_record(bag)
    try:
        value = float(record["config"]["limits"]["velocity_m_s"])
    except (TypeError, KeyError, ValueError):  # no record, no limits section: the default bound
        return railvib_contracts.DEFAULT_VELOCITY_LIMIT_M_S
    return value if math.isfinite(value) and value > 0 else railvib_contracts.DEFAULT_VELOCITY_LIMIT_M_S


def _check_messages(bag, info, result):
    """Every recorded metrics, snapshot and transform message holds to the message contract
    (scripts/railvib_contracts.py): a reader would otherwise plot or trust a NaN, a sensor the run
    does not have, or a grid its values do not fill. The first bad message refuses the bag."""
    if result.refused:
        return
    velocity = _recorded_velocity_limit(bag)
    sensors = []
    for _, m, _ in bag.read_messages(topics=[names.SENSOR_SAMPLES]):
        sensors = list(m.sensor_names)
        break
    checks = {}
    for topic in info:
        kind = TYPES.get(topic) or sensor_topic_type(topic)
        if kind == "railvib/VibrationMetrics":
            checks[topic] = lambda t, m: railvib_contracts.metrics_problem(t, m, velocity, sensors)
        elif kind == "railvib/SurfaceSnapshot":
            checks[topic] = lambda t, m: railvib_contracts.surface_snapshot_problem(t, m, velocity)
        elif kind == "railvib/SectionSnapshot":
            checks[topic] = lambda t, m: railvib_contracts.section_snapshot_problem(t, m, velocity)
        elif kind == "tf2_msgs/TFMessage":
            checks[topic] = railvib_contracts.tf_message_problem
    if not checks:
        return
    for topic, m, stamp in bag.read_messages(topics=sorted(checks)):
        problem = checks[topic](topic, m)
        if problem:
            result.refused = f"a recorded message at t = {stamp.to_sec():.6g} s breaks the message contract: {problem}"
            return


def sensor_topic_type(topic):
    """The type of a per-sensor topic /sensors/<name>/<what>, None for any other topic."""
    parts = topic.split("/")
    if len(parts) == 4 and parts[0] == "" and parts[1] == "sensors" and parts[2]:
        return SENSOR_TOPIC_TYPES.get(parts[3])
    return None


def _check_sensor_topics(bag, info, result):
    """Each sensor's standard topics hold one message per sample of /sensor_samples: none lost."""
    if names.SENSOR_SAMPLES not in info or result.refused:
        return
    samples = 0
    sensor_names = []
    for _, m, _ in bag.read_messages(topics=[names.SENSOR_SAMPLES]):
        samples += m.sample_count
        sensor_names = list(m.sensor_names)
    for sensor in sensor_names:
        for what in ("imu", "velocity"):
            topic = names.sensor_topic(sensor, what)
            if topic in info and info[topic].message_count != samples:
                result.findings.append(f"{topic}: {info[topic].message_count} messages for the {samples} samples of "
                                       f"{names.SENSOR_SAMPLES}")


def main(argv):
    if len(argv) != 2:
        print("usage: bag_check.py BAG", file=sys.stderr)
        return 2
    r = check_bag(argv[1])
    for n in r.notes:
        print(f"railvib bag check: note: {n}", file=sys.stderr)
    if r.refused:
        print(f"railvib bag check: refused: {r.refused}", file=sys.stderr)
    for f in r.findings:
        print(f"railvib bag check: {f}", file=sys.stderr)
    if r.code == 0:
        print(f"railvib bag check: {argv[1]}: every expected stream complete ({', '.join(r.expected)})")
    elif r.code == 1:
        print(f"railvib bag check: {argv[1]}: incomplete run"
              + (f", streams stopped early or missing: {', '.join(r.incomplete)}" if r.incomplete else ""),
              file=sys.stderr)
    return r.code


if __name__ == "__main__":
    sys.exit(main(sys.argv))
