#!/usr/bin/env python3
"""Node-level fuzz: each railvib stream node alone, fed mutated messages.

Every case starts one node (track, soil, building, virtual_sensor or recorder)
on a master of its own with the CI scenario (config/haren_ci.yaml), publishes
its latched layouts and a few blocks, one of them mutated (counts, sizes,
periods, NaN/inf, huge values, gaps, duplicates, blocks after the end, layouts
that do not match), and asserts a clean refusal: the node exits with code 1,
its output and its ERROR on /diagnostics name the stream and the field, and no
crash or sanitizer report appears. Control cases feed valid streams and expect
the node to finish ("finished" on /diagnostics) and exit 0 on SIGINT.

usage: node_fuzz.py [--junit FILE] [--json FILE] [--nodes track,soil,...] [--only SUBSTRING]

Outcome of a case: refused (clean refusal as above), crash (a signal, a
sanitizer report, a traceback), silent (the node accepted the bad input), or,
for a control case, finished / failed.
"""
import argparse
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
import xml.etree.ElementTree as ET

HERE = pathlib.Path(__file__).resolve()
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import railvib_names as names  # noqa: E402
from railvib_paths import find_railvib_tool  # noqa: E402
import railvib_process  # noqa: E402
sys.path.insert(0, str(HERE.parent))
from junit_xml import xml_text  # noqa: E402

CRASH_MARKERS = ("AddressSanitizer", "UndefinedBehaviorSanitizer", "runtime error:", "LeakSanitizer",
                 "Segmentation fault", "Aborted", "Traceback", "terminate called", "core dumped")
CONFIG = str(ROOT / "config" / "haren_ci.yaml")
# The publisher of a SurfaceSnapshot on the section snapshot's topic (a message of another type).
WRONG_TYPE = "section_snapshot as a SurfaceSnapshot"
STARTUP_S = float(os.environ.get("RAILVIB_FUZZ_STARTUP_S", "120"))
OUTCOME_S = float(os.environ.get("RAILVIB_FUZZ_OUTCOME_S", "90"))
DIAGNOSTICS_S = 15.0  # the longest wait for a refusing node's ERROR on /diagnostics after it exited


def node_binary(name):
    for prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep):
        candidate = os.path.join(prefix, "lib", "railvib", name)
        if prefix and os.access(candidate, os.X_OK):
            return candidate
    raise SystemExit(f"node_fuzz: {name} not found on CMAKE_PREFIX_PATH (run in the workspace environment)")


def scenario_summary():
    out = subprocess.run([find_railvib_tool(), "config-check", "--config", CONFIG], capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit("node_fuzz: config-check failed: " + out.stderr)
    return json.loads(out.stdout)


class Harness:
    """One master, one rospy node publishing the inputs and listening to /diagnostics."""

    def __init__(self, port):
        self.port = port
        self.env = dict(os.environ, ROS_MASTER_URI=f"http://localhost:{port}")
        os.environ["ROS_MASTER_URI"] = self.env["ROS_MASTER_URI"]
        self.log_dir = pathlib.Path(tempfile.mkdtemp(prefix="railvib_node_fuzz_"))
        self.master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], stdout=subprocess.DEVNULL,
                                       stderr=subprocess.DEVNULL, env=self.env, start_new_session=True)
        import rosgraph
        deadline = time.time() + 30
        while not rosgraph.is_master_online(self.env["ROS_MASTER_URI"]):
            if time.time() > deadline:
                raise SystemExit("node_fuzz: the master did not start")
            time.sleep(0.1)
        import rospy
        from diagnostic_msgs.msg import DiagnosticArray
        import railvib.msg as rm
        from tf2_msgs.msg import TFMessage
        self.rospy, self.rm = rospy, rm
        rospy.init_node("node_fuzz", anonymous=True, disable_signals=True)
        rospy.set_param("/railvib/config_file", CONFIG)
        self.diagnostics = []
        rospy.Subscriber("/diagnostics", DiagnosticArray, self._on_diag, queue_size=1000)
        q = 10000
        self.pub = {
            names.CONTACT_FORCES: rospy.Publisher(names.CONTACT_FORCES, rm.ContactForces, queue_size=q),
            names.SOIL_LOADS: rospy.Publisher(names.SOIL_LOADS, rm.SoilLoads, queue_size=q),
            names.SURFACE_VELOCITIES: rospy.Publisher(names.SURFACE_VELOCITIES, rm.SurfaceVelocities, queue_size=q),
            names.BUILDING_RESPONSE: rospy.Publisher(names.BUILDING_RESPONSE, rm.BuildingResponse, queue_size=q),
            names.SLEEPER_LAYOUT: rospy.Publisher(names.SLEEPER_LAYOUT, rm.SleeperLayout, queue_size=1, latch=True),
            names.SURFACE_POINTS: rospy.Publisher(names.SURFACE_POINTS, rm.PointLayout, queue_size=1, latch=True),
            names.BUILDING_POINTS: rospy.Publisher(names.BUILDING_POINTS, rm.PointLayout, queue_size=1, latch=True),
            # What a foreign publisher may put on the non-stream topics the recorder records.
            names.SENSOR_METRICS: rospy.Publisher(names.SENSOR_METRICS, rm.VibrationMetrics, queue_size=q),
            names.SURFACE_SNAPSHOT: rospy.Publisher(names.SURFACE_SNAPSHOT, rm.SurfaceSnapshot, queue_size=q),
            WRONG_TYPE: rospy.Publisher(names.SECTION_SNAPSHOT, rm.SurfaceSnapshot, queue_size=q),
            "/tf": rospy.Publisher("/tf", TFMessage, queue_size=q),
        }

    def _on_diag(self, msg):
        for s in msg.status:
            self.diagnostics.append((s.name, s.level, s.message))

    def close(self):
        self.rospy.signal_shutdown("done")
        railvib_process.stop(self.master)


# ----------------------------------------------------------------- valid messages
class Scenario:
    def __init__(self, summary):
        lay = summary["layouts"]
        self.sleepers = lay["sleeper_x_m"]
        self.sleeper_length = lay["sleeper_length_m"]
        self.sleeper_width = lay["sleeper_width_m"]
        self.wheels = lay["wheels"]
        self.surface = lay["surface_points"]
        self.house = lay["building_points"]
        self.dt = 1.0 / summary["rates_hz"]["contact_forces"]
        self.load_dt = 1.0 / summary["rates_hz"]["soil_loads"]
        self.vel_dt = 1.0 / summary["rates_hz"]["surface_velocities"]


def header(msg, t):
    import rospy
    msg.header.stamp = rospy.Time.from_sec(t)
    msg.header.frame_id = "track"


def contact_block(sc, rm, first, count, eos=False):
    m = rm.ContactForces()
    header(m, first * sc.dt)
    m.first_sample_index, m.end_of_stream, m.sample_period_s, m.sample_count = first, eos, sc.dt, count
    m.wheel_count = sc.wheels
    m.wheel_rail = [0] * sc.wheels  # the half vehicle: every wheel on the left rail
    offsets = [0.0, 1.6667, 7.5, 9.1667, 15.0, 16.6667][: sc.wheels]
    for k in range(count):
        for w in range(sc.wheels):
            m.position_m.append(-2.0 + 8.333 * (first + k) * sc.dt - offsets[w])
            m.force_n.append(25000.0)
            m.unevenness_m.append(0.0)
    return m


def loads_block(sc, rm, first, count, eos=False):
    m = rm.SoilLoads()
    header(m, first * sc.load_dt)
    m.first_sample_index, m.end_of_stream, m.sample_period_s, m.sample_count = first, eos, sc.load_dt, count
    m.sleeper_count = len(sc.sleepers)
    m.seats_per_sleeper = 1
    m.force_n = [1.0e4 + 10.0 * k for k in range(count) for _ in sc.sleepers]
    return m


def velocity_values(count, points, first):
    return [1e-4 * math.sin(0.3 * (first + k) + p + c) for k in range(count) for p in range(points) for c in range(3)]


def surface_block(sc, rm, first, count, eos=False):
    m = rm.SurfaceVelocities()
    header(m, first * sc.vel_dt)
    m.first_sample_index, m.end_of_stream, m.sample_period_s, m.sample_count = first, eos, sc.vel_dt, count
    m.receiver_count = len(sc.surface)
    m.velocity_m_s = velocity_values(count, len(sc.surface), first)
    return m


def building_block(sc, rm, first, count, eos=False):
    m = rm.BuildingResponse()
    header(m, first * sc.vel_dt)
    m.first_sample_index, m.end_of_stream, m.sample_period_s, m.sample_count = first, eos, sc.vel_dt, count
    m.point_count = len(sc.house)
    m.velocity_m_s = velocity_values(count, len(sc.house), first)
    return m


def sleeper_layout(sc, rm):
    m = rm.SleeperLayout()
    m.header.frame_id = "track"
    m.position_m = list(sc.sleepers)
    m.length_m, m.width_m = sc.sleeper_length, sc.sleeper_width
    return m


def point_layout(rm, points):
    from geometry_msgs.msg import Point
    m = rm.PointLayout()
    m.header.frame_id = "track"
    for p in points:
        m.names.append(p["name"])
        m.positions.append(Point(p["x_m"], p["y_m"], p["z_m"]))
    return m


def surface_layout(sc, rm):
    return point_layout(rm, sc.surface)


def house_layout(sc, rm):
    return point_layout(rm, [{"name": n, "x_m": 0.0, "y_m": 8.0, "z_m": 2.5 * i} for i, n in enumerate(sc.house)])


def metrics_message(sc, rm, sensor="ground_2m", **changes):
    m = rm.VibrationMetrics()
    header(m, 0.05)
    m.sensor_name, m.kind, m.resolved_hz = sensor, 0, 50.0
    m.kb_f, m.kb_f_max, m.ppv_m_s, m.ppv_vertical_m_s = 0.1, 0.2, 1.2e-3, 1.0e-3
    m.governing_component, m.governing_ppv_m_s, m.dominant_frequency_hz, m.din4150_3_limit_m_s = 2, 1.0e-3, 30.0, 0.02
    m.third_octave_center_hz, m.third_octave_level_db = [25.0, 31.5, 40.0], [float("-inf"), 110.0, 105.0]
    m.din4150_2_verdict = m.din4150_3_verdict = m.verdict = 3
    m.din4150_2_a_u, m.din4150_2_a_o, m.din4150_2_a_r = 0.15, 3.0, 0.07
    for key, value in changes.items():
        setattr(m, key, value)
    return m


def snapshot_message(sc, rm, **changes):
    m = rm.SurfaceSnapshot()
    header(m, 0.05)
    m.origin_x_m, m.origin_y_m, m.spacing_x_m, m.spacing_y_m, m.nx, m.ny = -10.0, 1.0, 0.5, 0.5, 2, 2
    m.vertical_velocity_m_s = [1e-4, -1e-4, 2e-4, 0.0]
    for key, value in changes.items():
        setattr(m, key, value)
    return m


def tf_message(sc, rm, translation=(0.0, 15.0, 0.0), rotation=(0.0, 0.0, 0.0, 1.0)):
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage
    t = TransformStamped()
    header(t, 0.05)
    t.child_frame_id = "fuzz_frame"
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = translation
    q = t.transform.rotation
    q.x, q.y, q.z, q.w = rotation
    return TFMessage(transforms=[t])


def message(factory, **changes):
    return lambda sc, rm: factory(sc, rm, **changes)


# ----------------------------------------------------------------- cases
def mutate(fn):
    """A block factory whose message then goes through fn(message)."""
    def make(factory, first, count, eos=False):
        def build(sc, rm):
            m = factory(sc, rm, first, count, eos)
            fn(m)
            return m
        return build
    return make


def plain(factory, first, count, eos=False):
    return lambda sc, rm: factory(sc, rm, first, count, eos)


def setattr_(field, value):
    return mutate(lambda m: setattr(m, field, value))


def poke(field, index, value):
    def fn(m):
        arr = list(getattr(m, field))
        arr[index % len(arr)] = value
        setattr(m, field, arr)
    return mutate(fn)


def truncate(field, keep):
    return mutate(lambda m: setattr(m, field, list(getattr(m, field))[:keep]))


def one_short(field):
    """The array one value shorter than the block's own (whatever the layout's size)."""
    return mutate(lambda m: setattr(m, field, list(getattr(m, field))[:-1]))


NODES = {
    # node: executable, status name on /diagnostics, input streams, layouts it needs, private params
    "track": ("track_node", "railvib/track", [names.CONTACT_FORCES], [], {"required_subscribers": 0}),
    "soil": ("soil_node", "railvib/soil", [names.SOIL_LOADS], [names.SLEEPER_LAYOUT],
             {"required_subscribers": 0, "include_building_footprint": True}),
    "building": ("building_node", "railvib/building", [names.SURFACE_VELOCITIES], [names.SURFACE_POINTS],
                 {"required_subscribers": 0}),
    "virtual_sensor": ("virtual_sensor_node", "railvib/virtual_sensor",
                       [names.SURFACE_VELOCITIES, names.BUILDING_RESPONSE], [names.SURFACE_POINTS, names.BUILDING_POINTS],
                       {"required_subscribers": 0, "use_building": True}),
    "recorder": ("bag_recorder_node", "railvib/recorder", [names.CONTACT_FORCES], [], {}),
}


def cases():
    """(node, case name, layouts {topic: factory}, [(topic, block factory)], expected, fragment)."""
    C = []
    cf, sl, sv, br = names.CONTACT_FORCES, names.SOIL_LOADS, names.SURFACE_VELOCITIES, names.BUILDING_RESPONSE
    big = 4000000000
    # track: /contact_forces
    good = [(cf, plain(contact_block, 0, 50)), (cf, plain(contact_block, 50, 50, True))]
    C.append(("track", "valid stream (control)", {}, good, "finished", "finished"))
    for name, bad, frag in [
        ("wheel_count 1 with 6 wheels of data", setattr_("wheel_count", 1)(contact_block, 50, 50), "wheel_count = 1"),
        ("wheel_count huge", setattr_("wheel_count", big)(contact_block, 50, 50), "wheel_count = 4000000000"),
        ("sample_count huge, arrays small", setattr_("sample_count", big)(contact_block, 50, 50), "sample_count"),
        ("force NaN", poke("force_n", 7, float("nan"))(contact_block, 50, 50), "force_n[sample 51, wheel 1] = nan"),
        ("force +inf", poke("force_n", 3, float("inf"))(contact_block, 50, 50), "force_n[sample"),
        ("force 1e300", poke("force_n", 0, 1e300)(contact_block, 50, 50), "= 1e+300"),
        ("force 40000 kN", poke("force_n", 0, 4e7)(contact_block, 50, 50), "limits.contact_force_n"),
        ("position NaN", poke("position_m", 0, float("nan"))(contact_block, 50, 50), "position_m["),
        ("unevenness 5 m", poke("unevenness_m", 2, 5.0)(contact_block, 50, 50), "unevenness_m["),
        ("force_n truncated", truncate("force_n", 17)(contact_block, 50, 50), "force_n has 17 values"),
        ("unevenness_m empty", truncate("unevenness_m", 0)(contact_block, 50, 50), "unevenness_m has 0 values"),
        ("period 0", setattr_("sample_period_s", 0.0)(contact_block, 50, 50), "sample_period_s = 0"),
        ("period NaN", setattr_("sample_period_s", float("nan"))(contact_block, 50, 50), "sample_period_s = nan"),
        ("period of another rate", setattr_("sample_period_s", 2e-5)(contact_block, 50, 50), "differs"),
        ("gap of 10 samples", plain(contact_block, 60, 50), "samples lost"),
        ("block repeated", plain(contact_block, 0, 50), "duplicate or reordered"),
        ("index near overflow", setattr_("first_sample_index", 2**64 - 5)(contact_block, 50, 50), "first_sample_index"),
        ("wheel_rail missing", setattr_("wheel_rail", [])(contact_block, 50, 50), "wheel_rail has 0 values"),
        ("a wheel on the right rail of a half track", poke("wheel_rail", 1, 1)(contact_block, 50, 50),
         "wheel_rail[1] = 1"),
    ]:
        C.append(("track", name, {}, [(cf, plain(contact_block, 0, 50)), (cf, bad)], "refused", frag))
    C.append(("track", "block after end_of_stream", {}, good + [(cf, plain(contact_block, 100, 10))], "refused",
              "after the end_of_stream"))

    # soil: /soil_loads + /sleeper_layout
    lay = {names.SLEEPER_LAYOUT: sleeper_layout}
    good = [(sl, plain(loads_block, 0, 20)), (sl, plain(loads_block, 20, 20, True))]
    C.append(("soil", "valid stream (control)", lay, good, "finished", "finished"))
    for name, bad, frag in [
        ("sleeper_count 1 against the layout", setattr_("sleeper_count", 1)(loads_block, 20, 20), "sleeper_count = 1"),
        ("force NaN", poke("force_n", 5, float("nan"))(loads_block, 20, 20), "force_n[sample 20, sleeper 5] = nan"),
        ("force -inf", poke("force_n", 5, float("-inf"))(loads_block, 20, 20), "= -inf"),
        ("force 1e300", poke("force_n", 5, 1e300)(loads_block, 20, 20), "limits.soil_load_n"),
        ("force_n one short", one_short("force_n")(loads_block, 20, 20), "force_n has"),
        ("period 0", setattr_("sample_period_s", 0.0)(loads_block, 20, 20), "sample_period_s = 0"),
        ("period of another rate", setattr_("sample_period_s", 1e-3)(loads_block, 20, 20), "load_sample_rate_hz"),
        ("gap", plain(loads_block, 25, 20), "samples lost"),
        ("block repeated", plain(loads_block, 0, 20), "duplicate or reordered"),
        ("two seats per sleeper on a half track", setattr_("seats_per_sleeper", 2)(loads_block, 20, 20),
         "seats_per_sleeper = 2"),
        ("seats_per_sleeper 0", setattr_("seats_per_sleeper", 0)(loads_block, 20, 20), "seats_per_sleeper = 0"),
    ]:
        C.append(("soil", name, lay, [(sl, plain(loads_block, 0, 20)), (sl, bad)], "refused", frag))

    def sleepers_mut(fn):
        def make(sc, rm):
            m = sleeper_layout(sc, rm)
            fn(m)
            return m
        return {names.SLEEPER_LAYOUT: make}
    for name, layout, frag in [
        ("layout of 10 sleepers", sleepers_mut(lambda m: setattr(m, "position_m", m.position_m[:10])), "10 sleepers"),
        ("layout NaN position", sleepers_mut(lambda m: m.position_m.__setitem__(3, float("nan"))), "position_m[3] = nan"),
        ("layout not increasing", sleepers_mut(lambda m: m.position_m.__setitem__(3, -100.0)), "must increase"),
        ("layout empty", sleepers_mut(lambda m: setattr(m, "position_m", [])), "holds 0 sleepers"),
        ("layout shifted 1 m", sleepers_mut(lambda m: setattr(m, "position_m", [x + 1 for x in m.position_m])),
         "the track config puts it at"),
        ("footprint NaN", sleepers_mut(lambda m: setattr(m, "length_m", float("nan"))), "length_m = nan"),
        ("rail seats on a half track", sleepers_mut(lambda m: setattr(m, "rail_seat_y_m", [0.7175, -0.7175])),
         "2 rail seats (rail_seat_y_m)"),
    ]:
        C.append(("soil", name, layout, [(sl, plain(loads_block, 0, 20))], "refused", frag))

    # building: /surface_velocities + /surface_points
    lay = {names.SURFACE_POINTS: surface_layout}
    good = [(sv, plain(surface_block, 0, 20)), (sv, plain(surface_block, 20, 20, True))]
    C.append(("building", "valid stream (control)", lay, good, "finished", "finished"))
    for name, bad, frag in [
        ("receiver_count 1 against the layout (read past the buffer before)",
         setattr_("receiver_count", 1)(surface_block, 20, 20), "receiver_count = 1"),
        ("receiver_count huge, array small", setattr_("receiver_count", big)(surface_block, 20, 20),
         "receiver_count = 4000000000"),
        ("velocity NaN", poke("velocity_m_s", 11, float("nan"))(surface_block, 20, 20), "velocity_m_s[sample 20"),
        ("velocity 1e300", poke("velocity_m_s", 11, 1e300)(surface_block, 20, 20), "limits.velocity_m_s"),
        ("velocity array truncated", truncate("velocity_m_s", 5)(surface_block, 20, 20), "velocity_m_s has 5 values"),
        ("period 0", setattr_("sample_period_s", 0.0)(surface_block, 20, 20), "sample_period_s = 0"),
        ("period of another rate", setattr_("sample_period_s", 5e-4)(surface_block, 20, 20), "receiver_rate_hz"),
        ("gap", plain(surface_block, 30, 20), "samples lost"),
        ("block repeated", plain(surface_block, 0, 20), "duplicate or reordered"),
    ]:
        C.append(("building", name, lay, [(sv, plain(surface_block, 0, 20)), (sv, bad)], "refused", frag))

    def surface_mut(fn):
        def make(sc, rm):
            m = surface_layout(sc, rm)
            fn(m)
            return m
        return {names.SURFACE_POINTS: make}
    footprint = names.footprint_point(0, 0)
    C.append(("building", "layout without a footprint point",
              surface_mut(lambda m: m.names.__setitem__(m.names.index(footprint), "elsewhere")),
              [(sv, plain(surface_block, 0, 20))], "refused", f"footprint point '{footprint}'"))
    C.append(("building", "layout with a name twice", surface_mut(lambda m: m.names.__setitem__(1, m.names[0])),
              [(sv, plain(surface_block, 0, 20))], "refused", "repeats"))
    C.append(("building", "layout names and positions differ", surface_mut(lambda m: m.positions.pop()),
              [(sv, plain(surface_block, 0, 20))], "refused", "positions"))
    C.append(("building", "block after end_of_stream", lay, good + [(sv, plain(surface_block, 40, 5))], "refused",
              "after the end_of_stream"))

    # virtual sensors: /surface_velocities + /building_response and their layouts
    lay = {names.SURFACE_POINTS: surface_layout, names.BUILDING_POINTS: house_layout}
    good = [(sv, plain(surface_block, 0, 200)), (br, plain(building_block, 0, 200)),
            (sv, plain(surface_block, 200, 100, True)), (br, plain(building_block, 200, 100, True))]
    C.append(("virtual_sensor", "valid streams (control)", lay, good, "finished", "finished"))
    first = [(sv, plain(surface_block, 0, 20)), (br, plain(building_block, 0, 20))]
    for name, bad, frag in [
        ("soil receiver_count 1", (sv, setattr_("receiver_count", 1)(surface_block, 20, 20)), "receiver_count = 1"),
        ("soil receiver_count huge", (sv, setattr_("receiver_count", big)(surface_block, 20, 20)), "receiver_count"),
        ("house point_count 1000", (br, setattr_("point_count", 1000)(building_block, 20, 20)), "point_count = 1000"),
        ("soil period 0 (stopped the output before)", (sv, setattr_("sample_period_s", 0.0)(surface_block, 20, 20)),
         "sample_period_s = 0"),
        ("house period negative", (br, setattr_("sample_period_s", -1e-3)(building_block, 20, 20)),
         "sample_period_s = -0.001"),
        ("soil velocity NaN", (sv, poke("velocity_m_s", 4, float("nan"))(surface_block, 20, 20)), "= nan"),
        ("house velocity inf", (br, poke("velocity_m_s", 4, float("inf"))(building_block, 20, 20)), "= inf"),
        ("soil gap", (sv, plain(surface_block, 21, 20)), "samples lost"),
        ("house array one short", (br, truncate("velocity_m_s", 119)(building_block, 20, 20)), "has 119 values"),
    ]:
        C.append(("virtual_sensor", name, lay, first + [bad], "refused", frag))

    def vs_mut(fn):
        def make(sc, rm):
            m = surface_layout(sc, rm)
            fn(m)
            return m
        return {names.SURFACE_POINTS: make, names.BUILDING_POINTS: house_layout}
    C.append(("virtual_sensor", "layout without the sensor's point",
              vs_mut(lambda m: m.names.__setitem__(m.names.index("ground_2m"), "ground_3m")), first, "refused",
              "point 'ground_2m'"))
    C.append(("virtual_sensor", "layout position NaN", vs_mut(lambda m: setattr(m.positions[0], "x", float("nan"))),
              first, "refused", "= nan"))

    # recorder: /contact_forces as a stream of its own
    C.append(("recorder", "period NaN", {}, [(cf, plain(contact_block, 0, 50)),
                                          (cf, setattr_("sample_period_s", float("nan"))(contact_block, 50, 50))],
              "refused", "not a positive period"))
    C.append(("recorder", "gap", {}, [(cf, plain(contact_block, 0, 50)), (cf, plain(contact_block, 70, 50))],
              "refused", "samples lost"))
    C.append(("recorder", "block repeated", {}, [(cf, plain(contact_block, 0, 50)), (cf, plain(contact_block, 0, 50))],
              "refused", "duplicate or reordered"))
    C.append(("recorder", "existing bag", {}, [], "refused", "refusing to overwrite"))
    C.append(("recorder", "valid stream (control)", {}, [(cf, plain(contact_block, 0, 50)),
                                                       (cf, plain(contact_block, 50, 50, True))], "finished",
              "all streams complete"))
    # A foreign publisher's metrics, snapshots and transforms beside a valid run: the run is recorded
    # whole, the valid messages recorded, each bad one refused (named, with its publisher) and counted.
    nan, metrics, snap = float("nan"), names.SENSOR_METRICS, names.SURFACE_SNAPSHOT
    foreign = [(metrics, message(metrics_message)), (metrics, message(metrics_message, kb_f=nan)),
               (metrics, message(metrics_message, sensor="ghost")), (metrics, message(metrics_message, verdict=7)),
               (snap, message(snapshot_message)), (snap, message(snapshot_message, nx=1000)),
               (snap, message(snapshot_message, spacing_x_m=0.0)), (WRONG_TYPE, message(snapshot_message)),
               (snap, message(snapshot_message, velocity_x_m_s=[1e-5] * 4, velocity_y_m_s=[-1e-5] * 4)),
               (snap, message(snapshot_message, velocity_x_m_s=[1e-5] * 4)),
               ("/tf", message(tf_message)), ("/tf", message(tf_message, rotation=(0.0, 0.0, 0.0, 0.0))),
               ("/tf", message(tf_message, translation=(nan, 0.0, 0.0)))]
    C.append(("recorder", "foreign metrics, snapshots and transforms beside a valid stream (control)", {},
              [(cf, plain(contact_block, 0, 50))] + foreign + [(cf, plain(contact_block, 50, 50, True))], "finished",
              "all streams complete",
              {"topics": [metrics, snap, names.SECTION_SNAPSHOT], "tf_topics": ["/tf"],
               "recorded": {metrics: 1, snap: 2, "/tf": 1, names.SECTION_SNAPSHOT: 0},
               "refused": {metrics: 3, snap: 3, names.SECTION_SNAPSHOT: 1, "/tf": 2},
               "fragments": ["kb_f = nan", "sensor_name 'ghost' is not a sensor of the scenario", "verdict = 7",
                             "nx x ny = 1000 x 2", "spacing_x_m = 0", "velocity_y_m_s has 0 values",
                             "a railvib/SurfaceSnapshot (MD5",
                             "quaternion has norm 0", "translation.x = nan", "/node_fuzz"]}))
    return C


def connected(publisher, caller_id):
    """Whether the subscriber node caller_id is connected to publisher (rospy keeps the subscriber's
    caller id as the endpoint id of the connection)."""
    return any(getattr(c, "endpoint_id", None) == caller_id for c in list(publisher.impl.connections))


def run_case(h, sc, index, case):
    node, title, layouts, blocks, expected, fragment, *more = case
    extra = more[0] if more else {}
    exe, status_name, inputs, needs, params = NODES[node]
    inputs = sorted({topic for topic, _ in blocks}) if extra else inputs
    rospy, rm = h.rospy, h.rm
    name = f"fuzz_{node}_{index}"
    # Layouts first (latched): this case's, else the valid ones.
    defaults = {names.SLEEPER_LAYOUT: sleeper_layout, names.SURFACE_POINTS: surface_layout,
                names.BUILDING_POINTS: house_layout}
    for topic in needs:
        h.pub[topic].publish((layouts.get(topic) or defaults[topic])(sc, rm))
    if node == "soil" and expected != "finished":
        # The house's foundation in the soil (two-way) is built at the node's start and stepped in the control
        # case; a refusal is of the streams, at the node's boundary, where the house changes nothing: the
        # refusal cases start the soil without it (the node's most expensive start, under the sanitizers).
        params = dict(params, include_building_footprint=False)
    for key, value in params.items():
        rospy.set_param(f"/{name}/{key}", value)
    bag = h.log_dir / f"{name}.bag"
    if node == "recorder":
        rospy.set_param(f"/{name}/streams", [names.CONTACT_FORCES])
        rospy.set_param(f"/{name}/bag_path", str(bag))
        rospy.set_param(f"/{name}/linger_s", 0.2)
        rospy.set_param(f"/{name}/topics", extra.get("topics", []))
        rospy.set_param(f"/{name}/tf_topics", extra.get("tf_topics", []))
        if title == "existing bag":
            bag.write_bytes(b"an earlier run's results")
    log = open(h.log_dir / f"{name}.log", "w+")
    # Before the node starts: a refusal of a latched layout may come before the first block is sent.
    h.diagnostics = [d for d in h.diagnostics if d[0] != status_name]

    def node_errors():  # this node's ERRORs on /diagnostics so far
        return [d for d in h.diagnostics if d[0] == status_name and d[1] == 2]

    proc = subprocess.Popen([node_binary(exe), f"__name:={name}"], stdout=log, stderr=subprocess.STDOUT, env=h.env,
                            start_new_session=True)
    result = {"group": "node " + node, "case": title, "expected": expected}
    try:
        # Wait for this node's own subscriptions: the previous case's node may still count as a
        # connection for a moment, and a block sent to it would be lost (a false "silent").
        deadline = time.time() + STARTUP_S
        while proc.poll() is None and time.time() < deadline and blocks and not all(
                connected(h.pub[t], "/" + name) for t in inputs):
            time.sleep(0.05)
        for topic, build in blocks:
            if proc.poll() is not None:
                break
            h.pub[topic].publish(build(sc, rm))
            time.sleep(0.05)
        deadline = time.time() + OUTCOME_S
        finished = False
        while proc.poll() is None and time.time() < deadline:
            if expected == "finished" and any(d[0] == status_name and d[2] == "finished" for d in h.diagnostics):
                finished = True
                break
            if node == "recorder" and expected == "finished" and bag.exists() and proc.poll() is not None:
                break
            time.sleep(0.1)
        railvib_process.stop(proc)
        time.sleep(0.3)  # the last /diagnostics in flight
        # A refusal's ERROR is published before the node exits, but this process handles /diagnostics on
        # a thread of its own, which a loaded machine can hold back past those 0.3 s: wait for it (a
        # condition, bounded; only a node that did not refuse as expected waits the whole bound).
        deadline = time.time() + DIAGNOSTICS_S
        while (expected != "finished" and proc.returncode == 1 and time.time() < deadline
               and not any(fragment in e[2] for e in node_errors())):
            time.sleep(0.05)
    finally:
        log.seek(0)
        output = log.read()
        log.close()
    code = proc.returncode
    errors = node_errors()
    crash = code is not None and code < 0 and code != -signal.SIGINT
    marker = next((m for m in CRASH_MARKERS if m in output), None)
    result["exit_code"] = code
    if marker or crash:
        result["outcome"] = "crash"
        result["detail"] = marker or f"signal {-code}"
    elif expected == "finished":
        ok = code == 0 and (finished or node == "recorder") and fragment in output
        if node == "recorder":
            ok = ok and bag.exists()
        result["outcome"] = "finished" if ok else "failed"
        result["detail"] = "" if ok else f"exit {code}, finished={finished}"
    else:
        clean = code == 1 and fragment in output and any(fragment in e[2] for e in errors)
        if clean:
            result["outcome"] = "refused"
            result["detail"] = next(e[2] for e in errors if fragment in e[2])
        elif code == 0 or code is None or code == -signal.SIGINT:
            result["outcome"] = "silent"
            result["detail"] = f"exit {code}: the node did not refuse it"
        else:
            result["outcome"] = "unclear"
            result["detail"] = (f"exit {code}; fragment {'found' if fragment in output else 'MISSING'} in the "
                                f"output; {len(errors)} ERROR on /diagnostics: "
                                + "; ".join(e[2] for e in errors)[:300])
    if result["outcome"] not in ("refused", "finished"):
        result["log"] = output[-3000:]
    if node == "recorder" and bag.exists() and title != "existing bag":
        import rosbag
        try:
            with rosbag.Bag(str(bag)) as b:  # closed cleanly: indexed, readable
                result["bag_messages"] = b.get_message_count()
                if extra and result["outcome"] == "finished":
                    check_recorded(b, extra, output, result)
        except Exception as e:
            result["outcome"] = "crash"
            result["detail"] = f"the bag is not readable: {e}"
    return result


def check_recorded(bag, extra, output, result):
    """What a recorder fed foreign messages kept: the valid ones, and its count of the refused ones."""
    wrong = []
    for topic, count in extra["recorded"].items():
        got = bag.get_message_count(topic_filters=[topic])
        if got != count:
            wrong.append(f"{topic}: {got} recorded, {count} expected")
    status = {}
    for _, m, _ in bag.read_messages(topics=[names.RECORDING_STATUS]):
        status = json.loads(m.data)
    refused = {topic: entry.get("messages") for topic, entry in status.get("refused", {}).items()}
    if refused != extra["refused"]:
        wrong.append(f"refused per topic {refused}, expected {extra['refused']}")
    wrong += [f"'{f}' not in the recorder's output" for f in extra["fragments"] if f not in output]
    if wrong:
        result["outcome"] = "failed"
        result["detail"] = "; ".join(wrong)
        result["log"] = output[-3000:]


def run(selected_nodes=None, only=None, progress=True):
    port = railvib_process.free_port()
    h = Harness(port)
    sc = Scenario(scenario_summary())
    results = []
    try:
        for i, case in enumerate(cases()):
            if selected_nodes and case[0] not in selected_nodes:
                continue
            if only and only not in case[1]:
                continue
            started = time.monotonic()
            r = run_case(h, sc, i, case)
            r["seconds"] = round(time.monotonic() - started, 2)  # where the fuzz's time goes (the JSON)
            results.append(r)
            if progress:
                print(f"[{r['outcome']:>8}] {r['group']}: {r['case']}  {r.get('detail', '')[:160]}", flush=True)
    finally:
        h.close()
        # The nodes' logs and bags: kept, and named, when a case went wrong (the report has their tails).
        if results and all(r["outcome"] in ("refused", "finished") for r in results):
            shutil.rmtree(h.log_dir, ignore_errors=True)
        else:
            print(f"node_fuzz: the nodes' logs and bags are in {h.log_dir}", flush=True)
    return results


def write_junit(results, path):
    suite = ET.Element("testsuite", name="node_fuzz", tests=str(len(results)),
                       failures=str(sum(r["outcome"] not in ("refused", "finished") for r in results)))
    for r in results:
        case = ET.SubElement(suite, "testcase", classname="NodeFuzz." + r["group"].replace(" ", "_"), name=r["case"],
                             time=str(r.get("seconds", 0.0)))
        if r["outcome"] not in ("refused", "finished"):
            failure = ET.SubElement(case, "failure", message=r["outcome"])
            failure.text = xml_text(r.get("detail", "") + "\n" + r.get("log", ""))
    pathlib.Path(path).parent.mkdir(parents=True, exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)


def main(argv):
    railvib_process.interrupts_by_default()
    parser = argparse.ArgumentParser(description="railvib node-level fuzz")
    parser.add_argument("--junit")
    parser.add_argument("--json")
    parser.add_argument("--nodes")
    parser.add_argument("--only")
    options = parser.parse_args(argv[1:])
    results = run(options.nodes.split(",") if options.nodes else None, options.only)
    if options.junit:
        write_junit(results, options.junit)
    if options.json:
        pathlib.Path(options.json).write_text(json.dumps(results, indent=1))
    bad = [r for r in results if r["outcome"] not in ("refused", "finished")]
    print(f"node_fuzz: {len(results)} cases, {len(bad)} not refused cleanly")
    for r in bad:
        print(f"  {r['outcome']}: {r['group']}: {r['case']}: {r.get('detail', '')}\n{r.get('log', '')[-1500:]}")
    return 1 if bad or not results else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
