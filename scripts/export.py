#!/usr/bin/env python3
"""railvib export: a recorded scenario bag as files other tools open.

usage: ./railvib export BAG [OUTDIR] [--what csv,mat,vtk,house] [--every N]

Writes into OUTDIR (default: BAG without .bag + "_export"):
  csv/<stream>.csv      one row per sample, one column per channel (t_s first), for Excel or MATLAB:
                          contact_forces      wheel<k>_position_m, wheel<k>_force_n, wheel<k>_unevenness_m
                                              (full width: a wheel per rail, axle-major, the left first)
                          soil_loads          sleeper<k>_force_n (positions in csv/sleeper_layout.csv; full
                                              width: sleeper<k>_left_force_n, sleeper<k>_right_force_n)
                          surface_velocities  <receiver>_v{x,y,z}_m_s (positions in csv/surface_points.csv)
                          building_response   <point>_v{x,y,z}_m_s (positions in csv/building_points.csv)
                          sensor_samples      <sensor>_v{x,y,z}_m_s, <sensor>_a{x,y,z}_m_s2
  csv/metrics_<sensor>.csv  the sensor's live metrics (/sensor_metrics, ~10 Hz), one row per message:
                          t_s, kb_f, kb_f_max, ppv_m_s, ppv_vertical_m_s, governing_component,
                          governing_ppv_m_s, dominant_frequency_hz, din4150_3_limit_m_s, the verdicts
                          (din4150_2, din4150_3, sensor) and L_<fc>Hz_db: each one-third-octave velocity
                          level (dB re 1e-9 m/s) as of that message
  csv/third_octave_levels.csv  sensor, kind, band centre (Hz), level (dB re 1e-9 m/s) of the whole
                          record (the last metrics message of each sensor)
  railvib.mat           the same streams as MATLAB structs (scipy.io.savemat, MAT 5): per stream
                          t_s [samples x 1], the arrays [samples x channels (x 3)] and the names
                          and `metrics`, a struct per sensor: t_s, the values above [messages x 1],
                          third_octave_center_hz [bands], third_octave_level_db [messages x bands]
  vtk/surface.pvd       the soil surface's velocity as a VTK time series that ParaView opens: one
                          binary, zlib-compressed VTK XML file (.vtu, written by meshio) per
                          /surface_snapshot, frame track, m and m/s; point data velocity_m_s
                          (vx, vy, vz up), or vertical_velocity_m_s alone when the run recorded
                          soil.output.snapshot_components: vertical
  vtk/section.pvd       the vertical section (/section_snapshot) likewise, z up (z = -depth)
  vtk/building_modes.vtk  the house mesh and its fixed-base mode shapes in frame track
                          (railvib_tool building-modes on the scenario recorded in the bag)
--every N keeps every N-th snapshot (default 1: all). Streams the bag lacks are skipped and said so.
Exit code 0, 1 if the bag's run is incomplete (exported as far as it goes), 2 if the bag is refused.
"""
import argparse
import csv
import pathlib
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import numpy as np

import bag_check
import railvib_names as names
import railvib_verdicts as verdicts
import report
from railvib_paths import find_railvib_tool, OutputDirError, output_dir

try:
    import rosbag
    import yaml
except ImportError:  # pragma: no cover
    sys.exit("railvib export: python3-rosbag and python3-yaml are required (./railvib setup installs them)")

AXES = ("x", "y", "z")


def die(msg, code=2):
    print("railvib export: error: " + msg, file=sys.stderr)
    sys.exit(code)


def say(msg):
    print("railvib export: " + msg)


class Stream:
    """One stream's samples: time, named channel columns, and the arrays for the .mat file."""

    def __init__(self, topic, blocks):
        self.topic = topic
        self.name = topic.lstrip("/")
        period = blocks[0].sample_period_s
        count = sum(b.sample_count for b in blocks)
        self.t_s = (blocks[0].first_sample_index + np.arange(count)) * period
        self.columns = []  # (header, 1-D array)
        self.arrays = {}   # for the .mat struct

    def vector_columns(self, labels, values, unit_suffix, prefix="v"):
        """values [sample, label, 3] -> <label>_<prefix>x_<unit> ... columns."""
        for i, label in enumerate(labels):
            for c, axis in enumerate(AXES):
                self.columns.append((f"{label}_{prefix}{axis}_{unit_suffix}", values[:, i, c]))


def layout_points(bag, topic):
    point_names, positions = report.layout(bag, topic)
    return point_names, positions


def read_streams(bag):
    """Every railvib stream of the bag as a Stream (skipping those it lacks), plus the layouts."""
    streams, layouts = [], {}
    cf = report.read_stream(bag, names.CONTACT_FORCES)
    if cf:
        s = Stream(names.CONTACT_FORCES, cf)
        nw = cf[0].wheel_count
        fields = {f: report.stacked(cf, f, nw) for f in ("position_m", "force_n", "unevenness_m")}
        for w in range(nw):
            for f, values in fields.items():
                s.columns.append((f"wheel{w + 1}_{f}", values[:, w]))
        s.arrays.update(fields)
        streams.append(s)
    sl = report.read_stream(bag, names.SOIL_LOADS)
    if sl:
        s = Stream(names.SOIL_LOADS, sl)
        ns, seats = sl[0].sleeper_count, sl[0].seats_per_sleeper
        force = report.stacked(sl, "force_n", ns * seats)  # [sample][sleeper][seat]
        for k in range(ns):
            if seats == 1:
                s.columns.append((f"sleeper{k + 1}_force_n", force[:, k]))
            else:
                for seat in range(seats):
                    s.columns.append((f"sleeper{k + 1}_{report.RAIL_NAMES[seat]}_force_n", force[:, k * seats + seat]))
        s.arrays["force_n"] = force
        streams.append(s)
        for _, m, _ in bag.read_messages(topics=[names.SLEEPER_LAYOUT]):
            layouts["sleeper_layout"] = (["sleeper", "x_m"],
                                         [(k + 1, x) for k, x in enumerate(m.position_m)])
            s.arrays["sleeper_x_m"] = np.array(m.position_m)
            break
    for topic, layout_topic, count_field in ((names.SURFACE_VELOCITIES, names.SURFACE_POINTS, "receiver_count"),
                                             (names.BUILDING_RESPONSE, names.BUILDING_POINTS, "point_count")):
        blocks = report.read_stream(bag, topic)
        if not blocks:
            continue
        n = getattr(blocks[0], count_field)
        point_names, positions = layout_points(bag, layout_topic)
        if point_names is None or len(point_names) != n:
            say(f"{topic}: no matching {layout_topic} layout in the bag: points named by index")
            point_names, positions = [f"point{k + 1}" for k in range(n)], None
        s = Stream(topic, blocks)
        v = report.stacked(blocks, "velocity_m_s", n, 3)
        s.vector_columns(point_names, v, "m_s")
        s.arrays["velocity_m_s"] = v
        s.arrays["point_names"] = np.array(point_names, dtype=object)
        streams.append(s)
        if positions is not None:
            layouts[layout_topic.lstrip("/")] = (["name", "x_m", "y_m", "z_m"],
                                                 [(nm,) + tuple(p) for nm, p in zip(point_names, positions)])
            s.arrays["point_position_m"] = np.array(positions)
    ss = report.read_stream(bag, names.SENSOR_SAMPLES)
    if ss:
        s = Stream(names.SENSOR_SAMPLES, ss)
        sensors = list(ss[0].sensor_names)
        v = report.stacked(ss, "velocity_m_s", len(sensors), 3)
        a = report.stacked(ss, "acceleration_m_s2", len(sensors), 3)
        for i, sensor in enumerate(sensors):
            for c, axis in enumerate(AXES):
                s.columns.append((f"{sensor}_v{axis}_m_s", v[:, i, c]))
            for c, axis in enumerate(AXES):
                s.columns.append((f"{sensor}_a{axis}_m_s2", a[:, i, c]))
        s.arrays.update({"velocity_m_s": v, "acceleration_m_s2": a, "sensor_names": np.array(sensors, dtype=object)})
        streams.append(s)
    return streams, layouts


METRIC_VALUES = ("kb_f", "kb_f_max", "ppv_m_s", "ppv_vertical_m_s", "governing_component", "governing_ppv_m_s",
                 "dominant_frequency_hz", "din4150_3_limit_m_s")
METRIC_VERDICTS = ("din4150_2_verdict", "din4150_3_verdict", "verdict")


class SensorMetrics:
    """One sensor's recorded /sensor_metrics messages, in time order: the values the core computed, as they are."""

    def __init__(self, sensor, messages):
        self.sensor = sensor
        self.kind = verdicts.kind_name(messages[-1].kind)
        self.t_s = np.array([m.header.stamp.to_sec() for m in messages])
        self.values = {f: np.array([getattr(m, f) for m in messages], dtype=float) for f in METRIC_VALUES}
        self.verdicts = {f: [verdicts.verdict_name(getattr(m, f)) for m in messages] for f in METRIC_VERDICTS}
        centers = [tuple(m.third_octave_center_hz) for m in messages]
        self.center_hz = np.array(centers[-1])
        # The bands are the sensor's throughout (the metrics contract); a change is said, and the levels
        # kept as of the last message only.
        self.consistent_bands = all(c == centers[-1] for c in centers)
        if self.consistent_bands:
            self.level_db = np.array([list(m.third_octave_level_db) for m in messages], dtype=float).reshape(
                len(messages), len(self.center_hz))
        else:
            say(f"metrics of {sensor}: the bands change during the record; band levels of the last message only")
            self.level_db = np.array([list(messages[-1].third_octave_level_db)], dtype=float)


def read_metrics(bag):
    """Each sensor's metrics messages (/sensor_metrics) as SensorMetrics, in the order the sensors first report."""
    by_sensor = {}
    for _, m, _ in bag.read_messages(topics=[names.SENSOR_METRICS]):
        by_sensor.setdefault(m.sensor_name, []).append(m)
    out = []
    for sensor, messages in by_sensor.items():
        messages.sort(key=lambda m: m.header.stamp.to_sec())
        out.append(SensorMetrics(sensor, messages))
    return out


def band_label(center_hz):
    return f"L_{center_hz:g}Hz_db"


def write_metrics_csv(outdir, metrics):
    d = outdir / "csv"
    d.mkdir(parents=True, exist_ok=True)
    for sm in metrics:
        path = d / f"metrics_{sm.sensor}.csv"
        bands = sm.consistent_bands
        with open(path, "w", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(["t_s", *METRIC_VALUES, *METRIC_VERDICTS] + ([band_label(c) for c in sm.center_hz] if bands else []))
            for k, t in enumerate(sm.t_s):
                # governing_component: 0 x, 1 y, 2 z of the sensor's frame, an index, not a measure
                row = [repr(float(t))] + [str(int(sm.values[v][k])) if v == "governing_component"
                                          else repr(float(sm.values[v][k])) for v in METRIC_VALUES]
                row += [sm.verdicts[v][k] for v in METRIC_VERDICTS]
                if bands:
                    row += [repr(float(x)) for x in sm.level_db[k]]
                w.writerow(row)
        say(f"{path}: {len(sm.t_s)} metrics messages")
    if metrics:
        path = d / "third_octave_levels.csv"
        with open(path, "w", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(["sensor", "kind", "center_hz", "level_db"])
            for sm in metrics:
                for c, level in zip(sm.center_hz, sm.level_db[-1]):
                    w.writerow([sm.sensor, sm.kind, repr(float(c)), repr(float(level))])
        say(f"{path}: the whole record's one-third-octave levels of {len(metrics)} sensors")


def write_csv(outdir, streams, layouts):
    d = outdir / "csv"
    d.mkdir(parents=True, exist_ok=True)
    for s in streams:
        path = d / f"{s.name}.csv"
        table = np.column_stack([s.t_s] + [col for _, col in s.columns])
        # 17 significant digits: the doubles of the bag, read back exactly.
        np.savetxt(path, table, fmt="%.17g", delimiter=",", header=",".join(["t_s"] + [h for h, _ in s.columns]),
                   comments="")
        say(f"{path}: {len(s.t_s)} samples x {len(s.columns)} channels")
    for name, (header, rows) in layouts.items():
        with open(d / f"{name}.csv", "w", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(header)
            w.writerows(rows)


def write_mat(outdir, streams, metrics):
    try:
        import scipy.io
    except ImportError:
        die("--what mat needs python3-scipy (./railvib setup installs it)")
    content = {}
    for s in streams:
        struct = {"t_s": s.t_s.reshape(-1, 1), "sample_period_s": float(s.t_s[1] - s.t_s[0]) if len(s.t_s) > 1 else 0.0}
        struct.update(s.arrays)
        content[s.name] = struct
    if metrics:
        content["metrics"] = {
            sm.sensor: {"t_s": sm.t_s.reshape(-1, 1), "kind": sm.kind,
                        **{v: sm.values[v].reshape(-1, 1) for v in METRIC_VALUES},
                        **{v: np.array(sm.verdicts[v], dtype=object) for v in METRIC_VERDICTS},
                        "third_octave_center_hz": sm.center_hz, "third_octave_level_db": sm.level_db}
            for sm in metrics}
    path = outdir / "railvib.mat"
    scipy.io.savemat(str(path), content, do_compression=True, long_field_names=True)
    say(f"{path}: {', '.join(content)}")


def write_pvd(path, entries):
    """ParaView's collection file: one DataSet per (time_s, relative file)."""
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    coll = ET.SubElement(root, "Collection")
    for t, file in entries:
        ET.SubElement(coll, "DataSet", timestep=repr(float(t)), group="", part="0", file=file)
    ET.ElementTree(root).write(path, xml_declaration=True, encoding="utf-8")


def grid_quads(n_fast, n_slow):
    """The quadrilaterals of a structured grid of n_fast x n_slow points (fast index first)."""
    i, j = np.meshgrid(np.arange(n_fast - 1), np.arange(n_slow - 1), indexing="xy")
    a = (i + n_fast * j).ravel()
    return np.column_stack([a, a + 1, a + 1 + n_fast, a + n_fast])


def point_velocity(topic, m, count):
    """The snapshot's velocity as VTK point data: velocity_m_s [count x 3] (vx, vy, vz up; frame
    track) when the message carries the horizontal components, else vertical_velocity_m_s alone
    (the vertical is then velocity_m_s's Z component, not written twice)."""
    vz = np.asarray(m.vertical_velocity_m_s, dtype=np.float32)
    vx, vy = (np.asarray(getattr(m, f, []) or [], dtype=np.float32) for f in ("velocity_x_m_s", "velocity_y_m_s"))
    if not len(vx) and not len(vy):
        return {"vertical_velocity_m_s": vz}
    if len(vx) != count or len(vy) != count:
        die(f"{topic}: snapshot {m.sample_index} has {len(vx)} / {len(vy)} horizontal values for {count} points")
    return {"velocity_m_s": np.column_stack([vx, vy, vz])}


def write_grid(path, points, quads, point_data):
    """One snapshot as a VTK XML unstructured grid, binary and zlib-compressed (meshio). Points in
    float32 (a 1e-6 m step at 20 m) and int32 connectivity: a fifth less than doubles and int64."""
    import meshio  # checked in write_vtk
    mesh = meshio.Mesh(points.astype(np.float32), [("quad", quads.astype(np.int32))], point_data=point_data)
    meshio.write(str(path), mesh, file_format="vtu", binary=True, compression="zlib")


def surface_file(path, m):
    """One /surface_snapshot on the plane z = 0 of frame track (points x fastest, as the message)."""
    nx, ny = m.nx, m.ny
    if len(m.vertical_velocity_m_s) != nx * ny or nx < 1 or ny < 1:
        die(f"{names.SURFACE_SNAPSHOT}: snapshot {m.sample_index} has {len(m.vertical_velocity_m_s)} values "
            f"for a {nx} x {ny} grid")
    x = m.origin_x_m + m.spacing_x_m * np.arange(nx)
    y = m.origin_y_m + m.spacing_y_m * np.arange(ny)
    xx, yy = np.meshgrid(x, y, indexing="xy")
    points = np.column_stack([xx.ravel(), yy.ravel(), np.zeros(nx * ny)])
    write_grid(path, points, grid_quads(nx, ny), point_velocity(names.SURFACE_SNAPSHOT, m, nx * ny))
    return nx * ny


def section_file(path, m):
    """One /section_snapshot on the plane x = x_m (points y fastest, then depth; z = -depth, up)."""
    ny, nz = m.ny, len(m.depth_m)
    if len(m.vertical_velocity_m_s) != ny * nz or ny < 1 or nz < 1:
        die(f"{names.SECTION_SNAPSHOT}: snapshot {m.sample_index} has {len(m.vertical_velocity_m_s)} values "
            f"for {ny} columns x {nz} rows")
    y = m.origin_y_m + m.spacing_y_m * np.arange(ny)
    yy, zz = np.meshgrid(y, -np.asarray(m.depth_m, dtype=float), indexing="xy")
    points = np.column_stack([np.full(ny * nz, m.x_m), yy.ravel(), zz.ravel()])
    write_grid(path, points, grid_quads(ny, nz), point_velocity(names.SECTION_SNAPSHOT, m, ny * nz))
    return ny * nz


def write_vtk(outdir, bag, every):
    try:
        import meshio  # noqa: F401
    except ImportError:
        die("--what vtk needs python3-meshio (./railvib setup installs it)")
    d = outdir / "vtk"
    d.mkdir(parents=True, exist_ok=True)
    for topic, stem in ((names.SURFACE_SNAPSHOT, "surface"), (names.SECTION_SNAPSHOT, "section")):
        writer = surface_file if stem == "surface" else section_file
        entries, components = [], set()
        for k, (_, m, _) in enumerate(bag.read_messages(topics=[topic])):
            if k % every:
                continue
            file = f"{stem}_{m.sample_index:05d}.vtu"
            writer(d / file, m)
            components.add(3 if len(getattr(m, "velocity_x_m_s", []) or []) else 1)
            entries.append((m.header.stamp.to_sec(), file))
        if entries:
            write_pvd(d / f"{stem}.pvd", entries)
            size_mb = sum((d / f).stat().st_size for _, f in entries) / 1e6
            what = {frozenset({3}): "velocity_m_s (vx, vy, vz)",
                    frozenset({1}): "vertical_velocity_m_s only (recorded with snapshot_components: vertical)"}
            say(f"{d / (stem + '.pvd')}: {len(entries)} snapshots, {entries[0][0]:.3f}-{entries[-1][0]:.3f} s, "
                f"{what.get(frozenset(components), 'vertical_velocity_m_s, velocity_m_s where recorded')}, "
                f"{size_mb:.1f} MB")
        else:
            say(f"{topic}: not in the bag, no {stem}.pvd")


def write_house(outdir, record, why):
    """The house mesh and mode shapes in frame track, from the scenario the bag records."""
    if record is None or not isinstance(record.get("config"), dict):
        say(f"{names.SCENARIO}: {why or 'no config in the record'}: no house export")
        return
    if "building" not in record["config"]:
        say("the recorded scenario has no house: no building_modes.vtk")
        return
    exe = find_railvib_tool()
    if not exe:
        die("railvib_tool not found: build with ./railvib setup")
    d = outdir / "vtk"
    d.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(record["config"], f)
        config_path = f.name
    out = subprocess.run([exe, "building-modes", "--config", config_path, "--vtk", str(d), "--vtk-frame", "track"],
                         capture_output=True, text=True)
    pathlib.Path(config_path).unlink()
    if out.returncode != 0:
        die(f"railvib_tool building-modes failed: {out.stderr.strip()}", code=1)
    say(f"{d / 'building_modes.vtk'}: the house and its fixed-base modes, frame track")


def main(argv):
    parser = argparse.ArgumentParser(prog="./railvib export", description=__doc__.split("\n")[0])
    parser.add_argument("bag")
    parser.add_argument("outdir", nargs="?")
    parser.add_argument("--what", default="csv,mat,vtk,house", help="comma-separated: csv, mat, vtk, house")
    parser.add_argument("--every", type=int, default=1, help="keep every N-th snapshot in the VTK series")
    options = parser.parse_args(argv[1:])
    what = {w.strip() for w in options.what.split(",") if w.strip()}
    unknown = what - {"csv", "mat", "vtk", "house"}
    if unknown:
        die("--what: unknown " + ", ".join(sorted(unknown)) + " (csv, mat, vtk, house)")
    if options.every < 1:
        die("--every must be >= 1")
    bag_path = pathlib.Path(options.bag)
    if not bag_path.exists():
        die(f"no such bag: {bag_path}")
    outdir = pathlib.Path(options.outdir) if options.outdir else bag_path.with_name(bag_path.stem + "_export")
    checked = bag_check.check_bag(bag_path)
    if checked.refused:
        die(checked.refused)
    for finding in checked.findings:
        print("railvib export: " + finding, file=sys.stderr)
    try:
        output_dir(outdir)
    except OutputDirError as e:
        die(str(e))
    try:
        bag = rosbag.Bag(str(bag_path))
    except Exception as e:  # rosbag raises several types for truncated or corrupt files
        die(f"cannot read {bag_path}: {e}")
    with bag:
        if what & {"csv", "mat"}:
            streams, layouts = read_streams(bag)
            metrics = read_metrics(bag)
            if "csv" in what:
                write_csv(outdir, streams, layouts)
                write_metrics_csv(outdir, metrics)
            if "mat" in what:
                write_mat(outdir, streams, metrics)
        if "vtk" in what:
            write_vtk(outdir, bag, options.every)
        record, why = report.scenario_record(bag)
    if "house" in what:
        write_house(outdir, record, why)
    if checked.incomplete:
        print("railvib export: incomplete run, streams stopped early: " + ", ".join(checked.incomplete),
              file=sys.stderr)
        return 1
    return 1 if checked.code else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
