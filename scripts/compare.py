#!/usr/bin/env python3
"""railvib compare: two runs side by side; for a one-way and a two-way run, the house's effect on the soil
(paper Figs. 15, 16).

usage: ./railvib compare BAG_A BAG_B [OUTDIR] [--at T ...] [--window S] [--config FILE] [--set key=value ...]
       ./railvib compare MEASURED.csv BAG [OUTDIR] --sensor NAME [--axes X,Y,Z] [--offset-s T]

A measured record (the velocity CSV of `./railvib import`: t_s and channels in m/s) against one sensor of a
run: --sensor names the run's sensor it was measured at; --axes the record's columns for x, y, z (frame
track; '-' for an axis not measured; default: three channels are x, y, z, one channel is z); the record is
resampled to the run's rate and shifted in time to the lag of the largest cross-correlation of v_z
(--offset-s T: the record's t = 0 is the run's t = T instead). OUTDIR gets sensors.png (both records: v_z,
its Fourier transform, KB_F(t)), compare.md / compare.json with PPV, KB_Fmax, dominant frequency and the
one-third-octave levels of v_z per band with the difference simulated - measured (dB).

Any two runs (e.g. two speeds, CLM vs Winkler, a study's runs): when either bag has no house, OUTDIR
(default: BAG_B without .bag + "_vs_" + BAG_A's name) gets
  sensors.png   each sensor both runs have: v_z of A and B, its Fourier transform magnitude and KB_F(t);
  compare.md    per sensor and run: PPV_z, vector PPV, KB_Fmax, dominant frequency of v_z (from
                `railvib_tool metrics`, the core's code), and B - A, B / A; the contact forces of the
                wheels both runs have (static, min, max); compare.json the same.
When both have the house, the house's effect (FREE_BAG = A, HOUSE_BAG = B):

FREE_BAG:  a run whose soil does not see the house (building.coupling: one_way; its receiver at the
           house's response point is the free field without the house, and its house is driven by it);
HOUSE_BAG: the same run with building.coupling: two_way (the foundation and the house act on the soil).

Writes into OUTDIR (default: HOUSE_BAG without .bag + "_vs_free_field"):
  floors_vs_free_field.png  ground and first floor, side by side with the free field: vertical velocity,
                            its Fourier transform magnitude in (mm/s)/Hz (report.spectrum, the report's
                            range and mesh marker) and KB_F(t) of the vertical component (DIN 4150-2,
                            from `railvib_tool metrics`, the core's code);
  section_snapshots.png     the paper's Fig. 16: vertical velocity on the vertical plane perpendicular to
                            the track through the defect and the house (/section_snapshot), without and
                            with the house, at the chosen times (--at; default: around the time the wave
                            field under the house peaks), the house and its embedded foundation marked;
  section.gif               the same planes as an animation over --window seconds around those times;
  compare.md                the metrics side by side and the one-third-octave levels of the soil at the
                            house's response point with and without the house.
--config/--set: the scenario of the runs (the foundation's depth is read from it, merged and checked by
`railvib_tool config-check --dump`).
"""
import argparse
import json
import pathlib
import subprocess
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

import bag_check  # noqa: E402
import railvib_names as names  # noqa: E402
import railvib_plots  # noqa: E402
import railvib_yaml  # noqa: E402
from railvib_paths import OutputDirError, output_dir  # noqa: E402
import report  # noqa: E402  (stream reading, spectra and metrics: one place)

try:
    import rosbag
except ImportError:  # pragma: no cover
    sys.exit("railvib compare: python3-rosbag is required (./railvib setup installs it)")

FLOORS = ("house_ground_floor", "house_first_floor")
BAND_RANGE_HZ = (8.0, 63.0)  # the one-third-octave bands shown: the mesh resolves up to 50 Hz


def die(msg):
    sys.exit("railvib compare: error: " + msg)


def check_whole(path):
    """Refuse a bag that is not railvib's or not whole (scripts/bag_check.py)."""
    checked = bag_check.check_bag(path)
    if checked.refused:
        die(f"{path}: {checked.refused}")
    if checked.incomplete:
        die(f"{path}: incomplete streams: {', '.join(checked.incomplete)}")


class SensorRun:
    """The virtual sensors of any railvib bag (the two-run comparison)."""

    def __init__(self, path):
        check_whole(path)
        with rosbag.Bag(str(path)) as bag:
            ss = report.read_stream(bag, names.SENSOR_SAMPLES)
            if not ss:
                die(f"{path}: no {names.SENSOR_SAMPLES} to compare")
            self.sensors = list(ss[0].sensor_names)
            self.v = report.stacked(ss, "velocity_m_s", len(self.sensors), 3)
            self.dt = ss[0].sample_period_s
            self.t = np.arange(len(self.v)) * self.dt
            scenario, _ = report.scenario_record(bag)
            self.record = scenario
            self.mesh_f_max_hz = report.config_number((scenario or {}).get("config"), "soil.mesh.f_max_hz")
            # The wheels' contact forces (when recorded): name, static (first sample), min and max per wheel.
            self.wheels = []
            cf = report.read_stream(bag, names.CONTACT_FORCES)
            if cf:
                nw = cf[0].wheel_count
                f = report.stacked(cf, "force_n", nw)
                wheel, _ = report.wheel_names((scenario or {}).get("config"), nw, list(cf[0].wheel_rail))
                self.wheels = [(wheel[w], f[0, w], f[:, w].min(), f[:, w].max()) for w in range(nw)]

    def has_house(self):
        return all(f in self.sensors for f in FLOORS)


class MeasuredRun:
    """A measured velocity record (./railvib import's CSV) as one sensor of a run: resampled to the run's
    rate, its axes mapped to x, y, z, and placed in the run's time (see the module's docstring)."""

    def __init__(self, path, sensor, run, axes=None, offset_s=None):
        from fractions import Fraction
        from scipy import signal
        path = pathlib.Path(path)
        if sensor not in run.sensors:
            die(f"--sensor {sensor}: the run has no such sensor ({', '.join(run.sensors)})")
        import measured_record
        try:
            self.axes, raw, rate = measured_record.velocity_axes(path, axes)
        except measured_record.RecordError as e:
            die(f"{e} (a measured record is the velocity CSV of ./railvib import)")
        ratio = Fraction(1.0 / (run.dt * rate)).limit_denominator(1000)
        if abs(float(ratio) * rate * run.dt - 1.0) > 1e-6:
            die(f"{path}: its rate {rate:g} Hz is no simple ratio of the run's {1 / run.dt:g} Hz")
        v = signal.resample_poly(raw, ratio.numerator, ratio.denominator, axis=0) if ratio != 1 else raw
        self.dt = run.dt
        if offset_s is None:
            # The lag (in the run's samples) at which the record's v_z best matches the run's.
            sim = run.v[:, run.sensors.index(sensor), 2]
            corr = signal.correlate(sim, v[:, 2], mode="full", method="fft")
            lag = int(np.argmax(corr)) - (len(v) - 1)
            offset_s = lag * self.dt
            self.alignment = f"shifted by {offset_s:+.4f} s (largest cross-correlation of v_z)"
        else:
            if not np.isfinite(offset_s):
                die(f"--offset-s {offset_s}: not a number")
            offset_s = round(offset_s / self.dt) * self.dt  # on the run's sample grid
            self.alignment = f"shifted by {offset_s:+.4f} s (--offset-s, to the run's nearest sample)"
        self.offset_s = offset_s
        self.t = offset_s + np.arange(len(v)) * self.dt
        self.v = v[:, None, :]
        self.sensors = [sensor]
        self.mesh_f_max_hz = None
        self.wheels = []


def level_differences(outdir, a, b, sensor, label_a, label_b):
    """One-third-octave levels of v_z of one sensor in a and b, and b - a per band (dB re 1e-9 m/s)."""
    la = metrics(a.t, a.v[:, a.sensors.index(sensor), :], outdir, f"{sensor}_bands_a")[2]
    lb = metrics(b.t, b.v[:, b.sensors.index(sensor), :], outdir, f"{sensor}_bands_b")[2]
    lines = ["", f"One-third-octave levels of v_z at {sensor} (dB re 1e-9 m/s):", "",
             f"| band [Hz] | {label_a} | {label_b} | {label_b} - {label_a} [dB] |", "|---|---|---|---|"]
    bands = []
    for f in sorted(la):
        if f in lb:
            lines.append(f"| {f:g} | {la[f]:.1f} | {lb[f]:.1f} | {lb[f] - la[f]:+.1f} |")
            bands.append({"nominal_hz": f, "a_db": la[f], "b_db": lb[f], "difference_db": lb[f] - la[f]})
    return lines, bands


# What a scenario record holds that says nothing about the physics of the run.
NOT_THE_SCENARIO = ("bag", "config", "command_line", "railvib_version", "config_file", "output_dir")


def flattened(node, prefix=""):
    """{dotted key: value} of a nested mapping (lists as values)."""
    out = {}
    if isinstance(node, dict):
        for k, v in node.items():
            out.update(flattened(v, f"{prefix}{k}."))
    else:
        out[prefix[:-1]] = node
    return out


def differences(record_a, record_b):
    """[(key, value in A, value in B)] where the two runs' scenarios differ: the resolved configuration
    and the launch arguments of their records; None when a record is missing."""
    if not record_a or not record_b:
        return None
    a = flattened(record_a.get("config") or {})
    b = flattened(record_b.get("config") or {})
    for record, flat in ((record_a, a), (record_b, b)):
        for k, v in (record.get("launch_arguments") or {}).items():
            if k not in NOT_THE_SCENARIO:
                flat[f"launch {k}"] = v
    return [(k, a.get(k, "(unset)"), b.get(k, "(unset)")) for k in sorted(set(a) | set(b))
            if a.get(k, "(unset)") != b.get(k, "(unset)")]


def short(value, width=18):
    text = str(value)
    return text if len(text) <= width else text[:width - 1] + "~"


def run_labels(name_a, name_b, diffs, shown=2):
    """Legend labels that name what differs between the runs (the first `shown` keys, then how many more)."""
    if diffs is None:
        return name_a, name_b
    if not diffs:
        return f"{name_a} (same scenario)", f"{name_b} (same scenario)"
    more = f", +{len(diffs) - shown} more" if len(diffs) > shown else ""
    # A long key path by its last two parts (the table in compare.md gives it whole).
    keys = [".".join(k.split(".")[-2:]) if len(k) > 40 else k for k, _, _ in diffs[:shown]]
    label_a = ", ".join(f"{k}={short(a)}" for k, (_, a, _) in zip(keys, diffs)) + more
    label_b = ", ".join(f"{k}={short(b)}" for k, (_, _, b) in zip(keys, diffs)) + more
    return f"{name_a}: {label_a}", f"{name_b}: {label_b}"


def compare_sensors(a, b, name_a, name_b, outdir, measured=None):
    """Each common sensor of runs a and b: figure, Markdown table and JSON of the metric differences
    (MEASURED: a is a measured record, and the levels per band are given as simulated - measured)."""
    common = [s for s in a.sensors if s in b.sensors]
    if not common:
        die(f"the runs have no sensor in common ({', '.join(a.sensors)} / {', '.join(b.sensors)})")
    fig, axes = plt.subplots(len(common), 3, figsize=(15, 2.8 * len(common) + 0.5), squeeze=False,
                             constrained_layout=True)
    rows = {}
    mesh = [m for m in (a.mesh_f_max_hz, b.mesh_f_max_hz) if m is not None]
    diffs = None if measured else differences(getattr(a, "record", None), getattr(b, "record", None))
    label_a, label_b = run_labels(name_a, name_b, diffs)
    if measured:
        label_a, label_b = f"{name_a} (measured)", f"{name_b} (simulated)"
    for i, sensor in enumerate(common):
        results = {}
        for run, label, colour, tag in ((a, label_a, "C0", "a"), (b, label_b, "C3", "b")):
            v = run.v[:, run.sensors.index(sensor), :]
            summary, kbf, _ = metrics(run.t, v, outdir, f"{sensor}_{tag}")
            results[tag] = summary
            axes[i][0].plot(run.t, v[:, 2] * 1e3, color=colour, lw=0.6, label=label)
            fr, amp = report.spectrum(run.t, v[:, 2] * 1e3)
            axes[i][1].plot(fr, amp, color=colour, lw=0.7, label=label)
            axes[i][2].plot(kbf["t_s"], kbf["kb_f_vz"], color=colour, lw=0.8, label=label)
        report.spectrum_axes(axes[i][1], report.spectrum_range_hz(1.0 / a.dt, 1.0 / b.dt), min(mesh) if mesh else None)
        axes[i][0].set_ylabel(f"{sensor}\nv_z [mm/s]")
        axes[i][2].set_ylabel("KB_F(t) of v_z [-]")
        for ax, xl in zip(axes[i], ("time [s]", "frequency [Hz]", "time [s]")):
            ax.set_xlabel(xl)
            ax.grid(alpha=0.3)
        axes[i][0].legend(fontsize=7, loc="upper right")

        def figures_of(summary):
            vz = summary["din4150_3"]["components"][2]
            return {"ppv_z_mm_s": vz["ppv_mm_s"], "vector_ppv_mm_s": summary["din4150_3"]["vector_peak_mm_s"],
                    "kb_fmax": summary["din4150_2"]["kb_fmax"], "dominant_frequency_z_hz": vz["dominant_frequency_hz"]}
        rows[sensor] = {"a": figures_of(results["a"]), "b": figures_of(results["b"])}
    railvib_plots.fit_title(fig, f"B: {name_b} (red) against A: {name_a} (blue)", fontsize=10)
    fig.savefig(outdir / "sensors.png", dpi=110)
    plt.close(fig)
    lines = [f"# railvib: `{name_b}` (B) against `{name_a}` (A)", "",
             "Per sensor: PPV of v_z, vector PPV, KB_Fmax (DIN 4150-2) and the dominant frequency of v_z, from "
             "`railvib_tool metrics` on each run's recorded samples (the core's code).", "",
             "| sensor | quantity | A | B | B - A | B / A |", "|---|---|---|---|---|---|"]
    for sensor, r in rows.items():
        for q in ("ppv_z_mm_s", "vector_ppv_mm_s", "kb_fmax", "dominant_frequency_z_hz"):
            x, y = r["a"][q], r["b"][q]
            ratio = f"{y / x:.3f}" if x else "-"
            lines.append(f"| {sensor} | {q} | {x:.4g} | {y:.4g} | {y - x:+.4g} | {ratio} |")
    wheels = {}
    if a.wheels and b.wheels:
        # Side by side by wheel name: the half and the full width name their wheels differently
        # (axle / axle and rail), so only the wheels both runs have are listed.
        b_of = {w[0]: w for w in b.wheels}
        lines += ["", "Contact forces per wheel, kN (static: the first sample):", "",
                  "| wheel | static A | static B | min A | min B | max A | max B | max B / A |",
                  "|---|---|---|---|---|---|---|---|"]
        for name, static, low, high in a.wheels:
            if name not in b_of:
                continue
            _, static_b, low_b, high_b = b_of[name]
            wheels[name] = {"a": {"static_n": static, "min_n": low, "max_n": high},
                            "b": {"static_n": static_b, "min_n": low_b, "max_n": high_b}}
            lines.append(f"| {name} | {static / 1e3:.2f} | {static_b / 1e3:.2f} | {low / 1e3:.2f} | {low_b / 1e3:.2f} "
                         f"| {high / 1e3:.2f} | {high_b / 1e3:.2f} | {high_b / high:.3f} |")
        if not wheels:
            lines.append("(no wheel of the same name in both runs)")
    bands = []
    if measured is not None:
        lines[0] = f"# railvib: the run `{name_b}` (B) against the measured record `{name_a}` (A)"
        lines += ["", f"The measured record: columns {', '.join(a.axes)} as x, y, z; resampled to "
                      f"{1 / a.dt:g} Hz and {a.alignment}."]
        band_lines, bands = level_differences(outdir, a, b, common[0], "measured", "simulated")
        lines += band_lines
    if diffs is not None:
        lines += ["", "What differs between the runs' scenarios (their records: the resolved configuration and the "
                      "launch arguments):", ""]
        if diffs:
            lines += ["| key | A | B |", "|---|---|---|"] + [f"| {k} | {va} | {vb} |" for k, va, vb in diffs]
        else:
            lines.append("nothing: the two runs had the same scenario.")
    elif not measured:
        lines += ["", "What differs between the runs is not known: a bag without its scenario record."]
    lines += ["", "![sensors](sensors.png)"]
    (outdir / "compare.md").write_text("\n".join(lines) + "\n")
    (outdir / "compare.json").write_text(json.dumps({"bag_a": name_a, "bag_b": name_b, "figures": ["sensors.png"],
                                                     "legend": [label_a, label_b],
                                                     "differences": None if diffs is None else
                                                     [{"key": k, "a": va, "b": vb} for k, va, vb in diffs],
                                                     "sensors": rows, "contact_forces": wheels,
                                                     "bands_z": bands,
                                                     "measured_offset_s": getattr(a, "offset_s", None)}, indent=1))
    print(f"railvib compare: {outdir / 'compare.md'} (sensors of two runs)")
    return 0


class Run:
    """The records of one bag that the comparison needs."""

    def __init__(self, path):
        check_whole(path)
        with rosbag.Bag(str(path)) as bag:
            ss = report.read_stream(bag, names.SENSOR_SAMPLES)
            sv = report.read_stream(bag, names.SURFACE_VELOCITIES)
            points, pos = report.layout(bag, names.SURFACE_POINTS)
            if not ss or not sv or not points:
                die(f"{path}: needs {names.SENSOR_SAMPLES}, {names.SURFACE_VELOCITIES} and {names.SURFACE_POINTS}")
            sensors = list(ss[0].sensor_names)
            missing = [f for f in FLOORS if f not in sensors]
            if missing or names.BUILDING_RESPONSE_FREE_FIELD_POINT not in points:
                die(f"{path}: a run with the house is needed (missing: "
                    f"{', '.join(missing + [names.BUILDING_RESPONSE_FREE_FIELD_POINT])})")
            v = report.stacked(ss, "velocity_m_s", len(sensors), 3)
            self.dt = ss[0].sample_period_s
            self.t = np.arange(len(v)) * self.dt
            self.floor = {f: v[:, sensors.index(f), :] for f in FLOORS}
            nr = sv[0].receiver_count
            r = report.stacked(sv, "velocity_m_s", nr, 3)
            if abs(sv[0].sample_period_s - self.dt) > 1e-12:
                die(f"{path}: receivers at {1 / sv[0].sample_period_s:g} Hz, sensors at {1 / self.dt:g} Hz")
            n = min(len(r), len(v))
            self.t = self.t[:n]
            self.floor = {f: x[:n] for f, x in self.floor.items()}
            self.soil_at_house = r[:n, points.index(names.BUILDING_RESPONSE_FREE_FIELD_POINT), :]
            house_y = [p[1] for name, p in zip(points, pos) if name.startswith("bldg_")]
            self.house_y = (min(house_y), max(house_y)) if house_y else None
            # The soil mesh's resolved frequency, marked on the spectra (None for a bag without the record).
            scenario, _ = report.scenario_record(bag)
            self.mesh_f_max_hz = report.config_number((scenario or {}).get("config"), "soil.mesh.f_max_hz")
            self.section_t, self.section = [], []
            for _, m, _ in bag.read_messages(topics=[names.SECTION_SNAPSHOT]):
                if len(m.vertical_velocity_m_s) != m.ny * len(m.depth_m):
                    die(f"{path}: a section snapshot of {len(m.vertical_velocity_m_s)} values for "
                        f"{m.ny} x {len(m.depth_m)}")
                self.section_t.append(m.header.stamp.to_sec())
                self.section.append(np.array(m.vertical_velocity_m_s, dtype=float).reshape(len(m.depth_m), m.ny))
                self.section_y = m.origin_y_m + m.spacing_y_m * np.arange(m.ny)
                self.section_depth = np.array(m.depth_m)
                self.section_x = m.x_m
            self.section_t = np.array(self.section_t)


def foundation_depth_m(config, overrides):
    exe = report.tool()
    cmd = exe + ["config-check", "--dump"] + (["--config", config] if config else [])
    for s in overrides:
        cmd += ["--set", s]
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        die("the scenario was refused: " + out.stderr.strip())
    return float(railvib_yaml.load(out.stdout)["building"]["foundation"]["depth_m"])


def metrics(t, v, outdir, name):
    summary, kbf = report.metrics(t, v, outdir, name)
    levels = {b["nominal_hz"]: b["level_db"] for b in summary["third_octave"]["components"][2]["levels"]}
    return summary, kbf, levels


def floors_figure(free, house, outdir):
    """Rows: ground floor, first floor; columns: v_z(t), |V_z|(f), KB_F(t) of v_z. Returns the metrics."""
    results = {"free field": metrics(free.t, free.soil_at_house, outdir, "free_field_at_house"),
               "soil under the house": metrics(house.t, house.soil_at_house, outdir, "soil_at_house_two_way")}
    fig, axes = plt.subplots(2, 3, figsize=(15, 7), squeeze=False)
    for row, floor in enumerate(FLOORS):
        results[f"{floor}, one-way"] = metrics(free.t, free.floor[floor], outdir, f"{floor}_one_way")
        results[f"{floor}, two-way"] = metrics(house.t, house.floor[floor], outdir, f"{floor}_two_way")
        curves = [("free field (one-way run's soil: no house)", free.t, free.soil_at_house, results["free field"],
                   "0.45"),
                  (f"{floor}, one-way (on the free field)", free.t, free.floor[floor], results[f"{floor}, one-way"],
                   "C0"),
                  (f"{floor}, two-way (on the soil)", house.t, house.floor[floor], results[f"{floor}, two-way"], "C3")]
        for label, t, v, (_, kbf, _), colour in curves:
            axes[row][0].plot(t, v[:, 2] * 1e3, color=colour, lw=0.6, label=label)
            fr, amp = report.spectrum(t, v[:, 2] * 1e3)
            axes[row][1].plot(fr, amp, color=colour, lw=0.7, label=label)
            axes[row][2].plot(kbf["t_s"], kbf["kb_f_vz"], color=colour, lw=0.8, label=label)
        axes[row][0].set_ylabel(f"{floor.replace('house_', '').replace('_', ' ')}\nv_z [mm/s]")
        axes[row][2].set_ylabel("KB_F(t) of v_z [-]")
        # The report's spectrum conventions: one range, the mesh's resolved frequency marked.
        mesh = [m for m in (free.mesh_f_max_hz, house.mesh_f_max_hz) if m is not None]
        report.spectrum_axes(axes[row][1], report.spectrum_range_hz(1.0 / free.dt, 1.0 / house.dt),
                             min(mesh) if mesh else None)
        for a, xl in zip(axes[row], ("time [s]", "frequency [Hz]", "time [s]")):
            a.set_xlabel(xl)
            a.grid(alpha=0.3)
        axes[row][0].legend(fontsize=7, loc="upper right")
    railvib_plots.fit_title(fig, "House response points vs the free field at the same place (paper Fig. 15)")
    fig.tight_layout()
    fig.savefig(outdir / "floors_vs_free_field.png", dpi=110)
    plt.close(fig)
    return results


def chosen_times(free, at, y_range):
    if at:
        return sorted(at)
    # Around the time the free field under the house peaks: the wave has reached it.
    mask = (free.section_y >= y_range[0]) & (free.section_y <= y_range[1])
    peak = [np.abs(s[:, mask]).max() for s in free.section]
    t0 = float(free.section_t[int(np.argmax(peak))])
    return [t0 - 0.06, t0 - 0.03, t0, t0 + 0.03]


def section_figures(free, house, outdir, times, window_s, depth_m):
    if not len(free.section) or not len(house.section):
        return []
    if free.section[0].shape != house.section[0].shape:
        die("the two runs' sections differ in size (not the same mesh)")
    # the house run's snapshot at the time of each of the free run's
    twin = [int(np.argmin(np.abs(house.section_t - t))) for t in free.section_t]
    nearest = [int(np.argmin(np.abs(free.section_t - t))) for t in times]
    frames = [free.section[i] for i in nearest] + [house.section[twin[i]] for i in nearest]
    y, z = free.section_y, free.section_depth
    # Colour scale from the plane in front of the house and beyond (the field under the track, 10 x
    # stronger, would saturate it and hide the house's effect).
    near_house = y >= (free.house_y[0] - 2.0 if free.house_y else y[0])
    lim = float(np.percentile(np.abs(np.concatenate([f[:, near_house].ravel() for f in frames])), 99.5)) * 1e3 or 1.0
    deepest = min(z[-1], 8.0)

    def draw(ax, field, title):
        im = ax.pcolormesh(y, z, field * 1e3, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="auto")
        ax.set_ylim(deepest, 0)
        ax.set_title(title, fontsize=8)
        if free.house_y:
            ax.add_patch(Rectangle((free.house_y[0], 0), free.house_y[1] - free.house_y[0], depth_m, fill=False,
                                   ec="k", lw=1.0))
            ax.plot(free.house_y, [0, 0], "k-", lw=3)
        ax.axvline(0.0, color="0.3", ls="--", lw=0.6)
        return im

    fig, axes = plt.subplots(2, len(nearest), figsize=(3.6 * len(nearest), 5.6), squeeze=False, sharey=True,
                             constrained_layout=True)
    for col, i in enumerate(nearest):
        j = twin[i]
        im = draw(axes[0][col], free.section[i], f"no house (one-way), t = {free.section_t[i]:.2f} s")
        draw(axes[1][col], house.section[j], f"with the house (two-way), t = {house.section_t[j]:.2f} s")
        axes[1][col].set_xlabel("distance from the track axis y [m]")
    for r in (0, 1):
        axes[r][0].set_ylabel("depth [m]")
    fig.colorbar(im, ax=axes, label="vertical velocity [mm/s]", shrink=0.8)
    railvib_plots.fit_title(fig, f"Vertical velocity on the plane x = {free.section_x:.2f} m (through the defect and "
                            "the house; paper Fig. 16); box: the house and its foundation; dashed: track axis", fontsize=9)
    fig.savefig(outdir / "section_snapshots.png", dpi=110)
    plt.close(fig)

    t_a, t_b = times[0] - 0.5 * window_s, times[-1] + 0.5 * window_s
    idx = [i for i, t in enumerate(free.section_t) if t_a <= t <= t_b]
    fig, axes = plt.subplots(2, 1, figsize=(7, 6.4), sharex=True, constrained_layout=True)
    ims = [draw(axes[0], free.section[idx[0]], ""), draw(axes[1], house.section[twin[idx[0]]], "")]
    axes[1].set_xlabel("distance from the track axis y [m]")
    for a in axes:
        a.set_ylabel("depth [m]")
    fig.colorbar(ims[0], ax=axes, label="vertical velocity [mm/s]", shrink=0.8)

    def frame(k):
        i = idx[k]
        j = twin[i]
        ims[0].set_array((free.section[i] * 1e3).ravel())
        ims[1].set_array((house.section[j] * 1e3).ravel())
        axes[0].set_title(f"no house (one-way), t = {free.section_t[i]:.2f} s", fontsize=9)
        axes[1].set_title(f"with the house (two-way), t = {house.section_t[j]:.2f} s", fontsize=9)
        return ims

    railvib_plots.save_gif(fig, frame, len(idx), outdir / "section.gif", fps=10, dpi=80)
    plt.close(fig)
    return ["section_snapshots.png", "section.gif"]


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("free_bag")
    ap.add_argument("house_bag")
    ap.add_argument("outdir", nargs="?")
    ap.add_argument("--at", type=float, action="append", default=[], help="snapshot time (s), repeatable")
    ap.add_argument("--window", type=float, default=0.3, help="animation length around the snapshot times (s)")
    ap.add_argument("--config", help="scenario of the runs (default: the tool's, config/haren.yaml)")
    ap.add_argument("--set", action="append", default=[], help="the runs' common overrides, key=value")
    ap.add_argument("--sensor", help="a measured record against this sensor of the run")
    ap.add_argument("--axes", help="the measured record's columns for x,y,z ('-': not measured)")
    ap.add_argument("--offset-s", type=float, help="the run's time of the measured record's t = 0 (s)")
    a = ap.parse_args(argv[1:])
    if a.free_bag.endswith(".csv") or a.sensor:
        # A measured record (first) against a run (second).
        if not a.free_bag.endswith(".csv") or not a.sensor:
            die("a measured record goes first, as ./railvib import's CSV, with --sensor NAME of the run")
        if not pathlib.Path(a.house_bag).exists():
            die(f"no such bag: {a.house_bag}")
        run = SensorRun(a.house_bag)
        measured = MeasuredRun(a.free_bag, a.sensor, run, a.axes.split(",") if a.axes else None, a.offset_s)
        bag = pathlib.Path(a.house_bag)
        outdir = pathlib.Path(a.outdir) if a.outdir else bag.with_name(bag.stem + "_vs_measured")
        try:
            output_dir(outdir)
        except OutputDirError as e:
            die(str(e))
        run.sensors, run.v = [a.sensor], run.v[:, [run.sensors.index(a.sensor)], :]
        # Both over the time they share: levels and KB_F of records of different lengths would differ
        # by their durations alone.
        t0, t1 = max(run.t[0], measured.t[0]), min(run.t[-1], measured.t[-1])
        if t1 - t0 < 1.0:
            die(f"the record and the run share {max(t1 - t0, 0.0):.3f} s once aligned ({measured.alignment}); "
                "at least 1 s is needed")
        for r in (run, measured):
            keep = (r.t >= t0 - 0.5 * run.dt) & (r.t <= t1 + 0.5 * run.dt)
            r.t, r.v = r.t[keep], r.v[keep]
        return compare_sensors(measured, run, pathlib.Path(a.free_bag).name, bag.name, outdir, measured=True)
    for p in (a.free_bag, a.house_bag):
        if not pathlib.Path(p).exists():
            die(f"no such bag: {p}")
    if a.window <= 0 or not np.isfinite(a.window):
        die(f"--window {a.window}: must be a positive number of seconds")
    house_bag = pathlib.Path(a.house_bag)
    run_a, run_b = SensorRun(a.free_bag), SensorRun(a.house_bag)
    couplings = []
    for path in (a.free_bag, a.house_bag):
        with rosbag.Bag(str(path)) as bag:
            couplings.append(report.recorded_coupling(bag)[0])
    if couplings == ["two_way", "one_way"]:
        die(f"{a.free_bag} ran two-way and {a.house_bag} one-way: give the free-field (one_way) run first")
    same_coupling = None not in couplings and couplings[0] == couplings[1]
    if not (run_a.has_house() and run_b.has_house()) or same_coupling:
        # Not a one-way / two-way pair (no house, or the same coupling twice): the sensors side by side.
        outdir = pathlib.Path(a.outdir) if a.outdir else house_bag.with_name(
            house_bag.stem + "_vs_" + pathlib.Path(a.free_bag).stem)
        try:
            output_dir(outdir)
        except OutputDirError as e:
            die(str(e))
        return compare_sensors(run_a, run_b, pathlib.Path(a.free_bag).name, house_bag.name, outdir)
    outdir = pathlib.Path(a.outdir) if a.outdir else house_bag.with_name(house_bag.stem + "_vs_free_field")
    try:
        output_dir(outdir)
    except OutputDirError as e:
        die(str(e))
    depth = foundation_depth_m(a.config, a.set)
    free, house = Run(a.free_bag), Run(a.house_bag)
    if abs(free.dt - house.dt) > 1e-12:
        die("the two runs' sensors have different rates")
    for t in a.at:
        if not (np.isfinite(t) and 0.0 <= t <= free.t[-1]):
            die(f"--at {t}: outside the record [0, {free.t[-1]:.3f}] s")

    results = floors_figure(free, house, outdir)
    figures = ["floors_vs_free_field.png"]
    times = chosen_times(free, a.at, free.house_y or (free.section_y[0], free.section_y[-1])) \
        if len(free.section) else []
    if times:
        figures += section_figures(free, house, outdir, times, a.window, depth)

    lines = [f"# railvib: the house's effect on the soil: `{house_bag.name}` against `{pathlib.Path(a.free_bag).name}`",
             "", "Free field: the one-way run's soil at the house's response point (its soil does not see the house; "
             "its house is driven by that free field). Two-way: the house and its foundation act on the soil; the "
             "soil at the response point is then the foundation's motion there. KB_F and PPV from "
             "`railvib_tool metrics` (DIN 4150-2 / -3, the core's code).", "",
             "| record | PPV_z [mm/s] | vector PPV [mm/s] | KB_Fmax | dominant frequency of v_z [Hz] |",
             "|---|---|---|---|---|"]
    for name, (summary, _, _) in results.items():
        vz = summary["din4150_3"]["components"][2]
        lines.append(f"| {name} | {vz['ppv_mm_s']:.3f} | {summary['din4150_3']['vector_peak_mm_s']:.3f} | "
                     f"{summary['din4150_2']['kb_fmax']:.4f} | {vz['dominant_frequency_hz']:.1f} |")
    free_levels, with_levels = results["free field"][2], results["soil under the house"][2]
    lines += ["", "One-third-octave levels of v_z (dB re 1e-9 m/s) at the house's response point:", "",
              "| band [Hz] | free field | soil under the house | difference [dB] | amplitude ratio |",
              "|---|---|---|---|---|"]
    for f in sorted(free_levels):
        if BAND_RANGE_HZ[0] <= f <= BAND_RANGE_HZ[1] and f in with_levels:
            d = with_levels[f] - free_levels[f]
            lines.append(f"| {f:g} | {free_levels[f]:.1f} | {with_levels[f]:.1f} | {d:+.1f} | {10 ** (d / 20):.2f} |")
    if times:
        lines += ["", "Section snapshots at t = " + ", ".join(f"{t:.2f}" for t in times) + " s."]
    lines += ["", "## Figures", ""] + [f"![{f}]({f})" for f in figures]
    (outdir / "compare.md").write_text("\n".join(lines) + "\n")
    records = {name: {"ppv_z_mm_s": r[0]["din4150_3"]["components"][2]["ppv_mm_s"],
                      "vector_ppv_mm_s": r[0]["din4150_3"]["vector_peak_mm_s"],
                      "kb_fmax": r[0]["din4150_2"]["kb_fmax"]} for name, r in results.items()}
    bands = [{"nominal_hz": f, "free_field_db": free_levels[f], "under_house_db": with_levels[f]}
             for f in sorted(free_levels) if BAND_RANGE_HZ[0] <= f <= BAND_RANGE_HZ[1] and f in with_levels]
    (outdir / "compare.json").write_text(json.dumps({"free_bag": str(a.free_bag), "house_bag": str(a.house_bag),
                                                     "snapshot_times_s": times, "figures": figures,
                                                     "records": records, "bands": bands}, indent=1))
    print(f"railvib compare: {outdir / 'compare.md'} ({len(figures)} figures)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
