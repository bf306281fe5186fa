#!/usr/bin/env python3
"""railvib report: figures and a Markdown summary from a recorded scenario bag.

usage: ./railvib report BAG [OUTDIR] [--exposure-s T]
       ./railvib report MEASURED.csv [OUTDIR] [--kind free_field|foundation|floor] [--axes X,Y,Z]
                        [--period day|night] [--exposure-s T]

Reads the railvib streams of the bag (whatever the scenario recorded):
  /railvib/scenario    the scenario record: version, command line, resolved configuration
  /contact_forces      contact forces at the defect
  /soil_loads          ballast-to-soil loads
  /surface_velocities  soil receivers (+ /surface_points names)
  /building_response   house response points (+ /building_points names)
  /sensor_samples      virtual sensors
  /sensor_metrics      the sensors' metrics and verdicts (the last message of each)
and writes into OUTDIR (default: BAG without .bag + "_report"):
  report.md            the scenario, the contact forces, the metric table (KB_Fmax, PPV, the
                       governing component, DIN 4150 verdicts: what the live sensors recorded in
                       the bag), the DIN 4150-2 exposure (KB_FTr) and the figures;
  *.png                contact forces (with a zoom on the impacts), sensors (time history,
                       spectrum, KB_F), standards (per sensor: one-third octave levels and each
                       component's PPV against the DIN 4150-3 guideline that applies there, drawn
                       as the live monitor draws them), wave field, house vs free field;
  scenario.yaml        the run's resolved configuration (after includes and overrides), when recorded;
  report.json          what the figures show (guide values, impact times, frequency range, windows),
                       for tests and scripts.
A measured record alone (the velocity CSV of `./railvib import`, t_s and channels in m/s): report.md
with its metrics and the verdicts of the standards that apply where it was measured (--kind, default
foundation; --axes as for ./railvib compare), sensors.png and standards.png as for a run's sensor,
report.json. The KB_F(t) curves and KB_FTr come from `railvib_tool metrics` on the recorded samples (the same core
code as the live sensors), never re-implemented here. --exposure-s: the DIN 4150-2 exposure time for
KB_FTr (default: the record length, one passage).
"""
import argparse
import csv
import json
import pathlib
import subprocess
import sys

import numpy as np
import yaml

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.transforms import blended_transform_factory  # noqa: E402

import bag_check  # noqa: E402
import railvib_names as names  # noqa: E402
import railvib_plots  # noqa: E402
import railvib_verdicts as verdicts  # noqa: E402
from railvib_paths import find_railvib_tool, OutputDirError, output_dir  # noqa: E402

try:
    import rosbag
except ImportError:  # pragma: no cover
    sys.exit("railvib report: python3-rosbag is required (./railvib setup installs it)")


INCOMPLETE = []  # streams whose last block is not flagged end_of_stream (the run stopped early)

# Every spectrum spans the same range: the band of ground-borne vibration from railways (DIN 4150-2
# weights 1-80 Hz) up to 100 Hz, or less if the sample rate is low (0.45 fs keeps clear of the
# anti-alias filter's transition band below the Nyquist frequency).
SPECTRUM_MAX_HZ = 100.0
SPECTRUM_MAX_FRACTION_OF_RATE = 0.45
# The contact-force zoom: from just before a wheel reaches the defect to after the impact has rung
# down (the P2 resonance of wheel on track, tens of Hz, decays within a few of its periods).
IMPACT_ZOOM_S = (-0.01, 0.04)
# The wave-field zoom: the first axle's impact and the wave's travel across the receiver line
# (Rayleigh waves at ~100-200 m/s cross 15 m in ~0.1 s; the tail rings for a few tenths of a second).
WAVE_WINDOW_S = 0.6
WAVE_WINDOW_LEAD_S = 0.1
# Receivers beyond the sleeper ends (|y| >= 2 m), where the field propagates freely.
NEAR_FIELD_Y_M = 2.0


def die(msg):
    sys.exit("railvib report: error: " + msg)


def read_stream(bag, topic):
    """Concatenate the blocks of a stream topic; checks continuity. Returns (t, data[sample][...]) or None."""
    blocks = [m for _, m, _ in bag.read_messages(topics=[topic])]
    if not blocks:
        return None
    blocks.sort(key=lambda m: m.first_sample_index)
    expected = 0
    for b in blocks:
        if b.first_sample_index != expected:
            die(f"{topic}: samples {expected}..{b.first_sample_index - 1} missing from the bag")
        expected += b.sample_count
    if not blocks[-1].end_of_stream and topic not in INCOMPLETE:
        INCOMPLETE.append(topic)
    return blocks


def stacked(blocks, field, *per_sample):
    """One array [sample, *per_sample] of a stream field over its blocks (in read_stream's order)."""
    return np.concatenate([np.array(getattr(b, field)).reshape(-1, *per_sample) for b in blocks])


def layout(bag, topic):
    for _, m, _ in bag.read_messages(topics=[topic]):
        return list(m.names), [(p.x, p.y, p.z) for p in m.positions]
    return None, None


def tool():
    exe = find_railvib_tool()
    if exe:
        return [exe]
    die("railvib_tool not found: build with ./railvib setup")


def sensor_kind(m):
    """Where a live sensor stood (VibrationMetrics.kind); None for a bag recorded before sensors said so."""
    return verdicts.kind_name(m.kind) if hasattr(m, "kind") else None


def verdict_text(value):
    """A live verdict as the report prints it: WARN is DIN 4150-2's middle case, which the rating decides."""
    return "WARN (rating KB_FTr decides)" if verdicts.verdict_name(value) == "WARN" else verdicts.verdict_name(value)
COMPONENTS = ["vx", "vy", "vz"]  # the columns railvib_tool metrics names them by
USAGE = ("./railvib report BAG [OUTDIR] [--exposure-s T] | ./railvib report MEASURED.csv [OUTDIR] "
         "[--kind free_field|foundation|floor] [--axes X,Y,Z] [--period day|night] [--exposure-s T]")
COMPONENT_COLOURS = {0: "C2", 1: "C1", 2: "C0"}


def last_metrics(bag):
    """The last VibrationMetrics of each sensor (it covers the whole record)."""
    last = {}
    for _, m, _ in bag.read_messages(topics=[names.SENSOR_METRICS]):
        last[m.sensor_name] = m
    return last


def metrics(t, v_m_s, outdir, name, exposure_s=None, period=None, kind=None, resolved_hz=None):
    """Run railvib_tool metrics on one sensor's 3 components; returns its JSON summary and KB_F(t).

    exposure_s, period: the DIN 4150-2 exposure time for KB_FTr and the guide values' period
    (the tool's defaults: the record length, day); kind, resolved_hz: where the sensor stands and the
    model's resolved frequency, as the live sensor judged it (the tool's defaults: foundation, no limit)."""
    path = outdir / f"{name}_velocity.csv"
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["t_s", "vx", "vy", "vz"])
        for i in range(len(t)):
            w.writerow([repr(t[i])] + [repr(x) for x in v_m_s[i]])
    cmd = tool() + ["metrics", "--csv", str(path), "--column", "vx,vy,vz", "--out", str(outdir / f"{name}_kbf.csv")]
    if exposure_s is not None:
        cmd += ["--exposure-s", repr(float(exposure_s))]
    if period is not None:
        cmd += ["--period", period]
    if kind is not None:
        cmd += ["--kind", kind]
    if resolved_hz:
        cmd += ["--resolved-hz", repr(float(resolved_hz))]
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        die(f"railvib_tool metrics failed for {name}: {out.stderr.strip()}")
    kbf = np.genfromtxt(outdir / f"{name}_kbf.csv", delimiter=",", names=True)
    return json.loads(out.stdout), kbf


def standards_figure(sensor_names, live, summaries, resolved_hz, path):
    """Per sensor, the figures the standards use (scripts/railvib_plots.py, as the live monitor draws
    them): the one-third octave band levels of the three components over the record, and each
    component's peak at its dominant frequency against the DIN 4150-3 guideline that applies where the
    sensor stands (none in the free field: drawn grey). Returns what was drawn, per sensor."""
    guidelines = railvib_plots.load_guidelines()
    ns = len(sensor_names)
    fig, axes = plt.subplots(ns, 2, figsize=(12, 2.9 * ns + 0.4), squeeze=False, constrained_layout=True)
    drawn = {}
    for i, name in enumerate(sensor_names):
        summary, kind = summaries[name], sensor_kind(live[name])
        bands = summary["third_octave"]["components"]
        centres = [b["nominal_hz"] for b in bands[0]["levels"]]
        levels = {c: [b["level_db"] for b in bands[c]["levels"]] for c in range(3)}
        railvib_plots.third_octave_bars(axes[i][0], centres, levels, resolved_hz)
        axes[i][0].set_title(f"{name}: one-third octave levels over the record, dB re 1e-9 m/s", loc="left",
                             fontsize=9)
        axes[i][0].legend(fontsize=6, loc="upper right", ncol=2)
        railvib_plots.din4150_3_axes(axes[i][1], guidelines, kind=kind, fontsize=9,
                                     title=f"{name} ({kind or 'kind not recorded'}): PPV vs DIN 4150-3",
                                     resolved_hz=resolved_hz)
        points = []
        for c, component in enumerate(summary["din4150_3"]["components"]):
            ppv, f = component["ppv_mm_s"], component["dominant_frequency_hz"]
            if ppv > 0 and f and f > 0:
                railvib_plots.mark_ppv(axes[i][1], f, ppv, c, label=f"v_{railvib_plots.COMPONENT_NAMES[c]}")
                points.append({"component": railvib_plots.COMPONENT_NAMES[c], "ppv_mm_s": ppv, "frequency_hz": f})
        axes[i][1].legend(fontsize=6, loc="best")
        axes[i][1].set_ylabel("PPV (mm/s)", fontsize=9)
        drawn[name] = {"kind": kind, "bands": len(centres), "ppv_points": points,
                       "guideline": "free field: not applicable" if kind == "free_field" else
                       ("floor values" if kind == "floor" else "foundation curve"),
                       "guideline_error": guidelines.error}
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return drawn


def names_in_order(ss, live):
    """Sensors in the order of the samples stream; each must have its recorded metrics."""
    order = list(ss[0].sensor_names)
    missing = [n for n in order if n not in live]
    if missing:
        die("no metrics recorded on " + names.SENSOR_METRICS + " for " + ", ".join(missing))
    return order


# ------------------------------------------------------------------ spectra
def spectrum(t, x):
    """Fourier transform magnitude of a record, |X(f)| = dt |FFT(x)|, on the one-sided frequencies.

    A passage is a transient, not a stationary signal: its spectrum is the magnitude of its Fourier
    transform (a density, unit of x per Hz: (mm/s)/Hz for a velocity in mm/s), with a rectangular
    window over the whole record, not an amplitude spectrum with a window normalisation (which holds
    for steady sines only; Bendat & Piersol, Random Data, "transient data"). A sine of amplitude A
    lasting T (whole periods) has |X| = A T / 2 at its frequency."""
    n = len(x)
    if n < 2:
        return np.array([0.0]), np.array([0.0])
    dt = t[1] - t[0]
    return np.fft.rfftfreq(n, dt), np.abs(np.fft.rfft(x)) * dt


def spectrum_range_hz(*rates_hz):
    """The upper frequency of every spectrum of a report: 100 Hz, or 0.45 x the lowest sample rate."""
    return min([SPECTRUM_MAX_HZ] + [SPECTRUM_MAX_FRACTION_OF_RATE * r for r in rates_hz if r > 0])


def spectrum_axes(ax, f_max_hz, mesh_f_max_hz, component="z"):
    """Range, labels and the soil mesh's resolved frequency (above it the results are not trustworthy).
    component: the one plotted (x, y, z), or None for several."""
    ax.set_xlim(0, f_max_hz)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel(f"|V{'_' + component if component else ''}(f)| [(mm/s)/Hz]")
    if mesh_f_max_hz is not None and mesh_f_max_hz < f_max_hz:
        ax.axvspan(mesh_f_max_hz, f_max_hz, color="0.88", lw=0, zorder=0)
    if mesh_f_max_hz is not None:
        ax.axvline(mesh_f_max_hz, color="k", ls=":", lw=1.0, label=f"mesh resolves up to {mesh_f_max_hz:g} Hz")


# ------------------------------------------------------------------ scenario record
# The scenario record (/railvib/scenario) as a dict, and why it is not there: read by the bag check.
scenario_record = bag_check.scenario_record


def config_value(config, path):
    """The value at a dotted key path of the resolved configuration, or None."""
    node = config
    for key in path.split("."):
        if not isinstance(node, dict) or key not in node:
            return None
        node = node[key]
    return node


def config_coupling(config):
    """building.coupling (one_way | two_way) of a resolved configuration, None without a house."""
    if config_value(config, "building") is None:
        return None
    value = config_value(config, "building.coupling")
    # A house section without the key ran one_way (the loader's default).
    return "one_way" if value is None else str(value)


def recorded_coupling(bag):
    """building.coupling of the run (one_way | two_way) as the bag's scenario record has it, and why not
    when it is not known (no record, a bag from an older railvib, no house)."""
    record, why_not = scenario_record(bag)
    if record is None:
        return None, why_not
    coupling = config_coupling(record.get("config"))
    return (coupling, None) if coupling else (None, "the recorded scenario has no house")


def config_number(config, path):
    value = config_value(config, path)
    if isinstance(value, bool):
        return None
    try:
        value = float(value)
    except (TypeError, ValueError):
        return None
    return value if np.isfinite(value) else None


def scenario_section(record, why_not, outdir):
    """The report's "Scenario" section; writes the resolved configuration to OUTDIR/scenario.yaml."""
    lines = ["## Scenario", ""]
    if record is None:
        return lines + [why_not[0].upper() + why_not[1:] + ": the mesh resolution, the defect position, the axle "
                        "names and the house placement are not known; the figures say what they use instead.", ""]

    def cell(value):
        text = "" if value is None else str(value)
        return text.replace("|", "\\|").replace("\n", " ") or "(not recorded)"

    arguments = record.get("launch_arguments") or {}
    given = [f"{k}:={v}" for k, v in sorted(arguments.items())] if isinstance(arguments, dict) else [str(arguments)]
    given = [a for a in given if not a.endswith(":=")]  # an empty argument keeps the config's value
    overrides = record.get("config_overrides") or []
    lines += ["| | |", "|---|---|",
              f"| railvib version | {cell(record.get('railvib_version'))} |",
              f"| command line | `{cell(record.get('command_line'))}` |",
              f"| config file | `{cell(record.get('config_file'))}` |",
              f"| launch arguments | {cell(', '.join(given) or 'none: the config file values')} |",
              f"| config overrides | {cell(', '.join(map(str, overrides)) or 'none')} |",
              f"| host | {cell(record.get('host'))} |",
              f"| recorded (UTC) | {cell(record.get('recorded_utc'))} |", ""]
    config = record.get("config")
    if isinstance(config, dict):
        with open(outdir / "scenario.yaml", "w") as f:
            f.write(f"# The resolved configuration of the run (after includes and overrides), as recorded in the "
                    f"bag ({names.SCENARIO}).\n")
            yaml.safe_dump(config, f, sort_keys=False, default_flow_style=False)
        lines += ["The resolved configuration (after includes, launch arguments and overrides): "
                  "[scenario.yaml](scenario.yaml).", ""]
    else:
        lines += ["The record holds no resolved configuration (`config`).", ""]
    return lines


# ------------------------------------------------------------------ DIN 4150-2 guide values
_GUIDES = []


def din_guides():
    """`railvib_tool din-guides` (the core's guide values), once; None if the tool has no such command."""
    if not _GUIDES:
        out = subprocess.run(tool() + ["din-guides"], capture_output=True, text=True)
        try:
            _GUIDES.append(json.loads(out.stdout) if out.returncode == 0 else None)
        except ValueError:
            _GUIDES.append(None)
    return _GUIDES[0]


def live_guides(m):
    """A_u, A_o of a VibrationMetrics message, or None (a bag recorded before the message had them)."""
    a_u, a_o = getattr(m, "din4150_2_a_u", None), getattr(m, "din4150_2_a_o", None)
    if a_u is None or a_o is None or not (a_u > 0 and a_o > a_u):
        return None
    return float(a_u), float(a_o)


def din_period(config, live):
    """The DIN 4150-2 period of the live verdicts (day | night) and where it comes from."""
    period = config_value(config, "virtual_sensors.din4150_2_period")
    if period in ("day", "night"):
        return period, "virtual_sensors.din4150_2_period of the scenario record"
    night = config_value(config, "virtual_sensors.night")
    if isinstance(night, bool):
        return ("night" if night else "day"), "virtual_sensors.night of the scenario record"
    recorded = [g for g in map(live_guides, live.values()) if g]
    guides = din_guides() if recorded else None
    if guides:
        for p in ("day", "night"):
            g = guides["din4150_2_residential"][p]
            if all(abs(a_u - g["a_u"]) < 1e-12 and abs(a_o - g["a_o"]) < 1e-12 for a_u, a_o in recorded):
                return p, f"the live sensors' guide values ({names.SENSOR_METRICS}) are the {p}'s"
    return "day", "not in the scenario record: day (the sensors' default)"


def guide_values(m, period):
    """A_u, A_o to draw on a sensor's KB_F plot and their source: the live sensor's, else the tool's."""
    g = live_guides(m) if m is not None else None
    if g:
        return g[0], g[1], f"the live sensor's ({names.SENSOR_METRICS})"
    guides = din_guides()
    if guides:
        v = guides["din4150_2_residential"][period]
        return float(v["a_u"]), float(v["a_o"]), f"`railvib_tool din-guides`, {period} (not in the bag's metrics)"
    return None, None, "not known (the bag's metrics lack them and railvib_tool has no din-guides)"


# Which live verdict each reason of the rated one (railvib_tool metrics) belongs to: the rating only
# completes the middle case.
_LIVE_OF_REASON = [("KB_Fmax <= A_u", 0), ("KB_Fmax > A_o", 2), ("A_u < KB_Fmax", 1)]


# ------------------------------------------------------------------ vehicle, defect, house
RAIL_NAMES = ("left", "right")  # ContactForces.wheel_rail codes: 0 = LEFT, 1 = RIGHT


def wheel_names(config, n, wheel_rail=None):
    """Names of the n wheels (wheel 0 = front axle): the vehicle's axle names if recorded, else axle 1..n;
    at full width (ContactForces.wheel_rail holds a right rail: a wheel per rail, axle-major) the axle's name
    and the wheel's rail."""
    rails = list(wheel_rail or [])
    full_width = len(rails) == n and any(r == 1 for r in rails)
    axles = n // 2 if full_width else n
    vehicle = config_value(config, "vehicle.name")
    wheels = config_value(config, f"vehicles.{vehicle}.wheels") if isinstance(vehicle, str) else None
    if isinstance(wheels, list) and len(wheels) == axles and all(isinstance(w, dict) and "name" in w for w in wheels):
        axle_names, how = [str(w["name"]) for w in wheels], f"vehicles.{vehicle}.wheels of the scenario record"
    else:
        axle_names, how = [f"axle {i + 1}" for i in range(axles)], \
            "axle 1..N from the front (no axle names in the scenario record)"
    if not full_width:
        return axle_names, how
    return [f"{axle_names[w // 2]} {RAIL_NAMES[rails[w]]}" for w in range(n)], how + ", a wheel per rail"


def defect_rails(config):
    """The rails the defect lies on (unevenness.defect.rails: both, left or right; absent: both)."""
    rails = config_value(config, "unevenness.defect.rails") if config is not None else None
    return {"left": (0,), "right": (1,)}.get(rails, (0, 1))


def defect_position_m(config):
    """The rail defect's position along the track, or (None, why not)."""
    if config is None:
        return None, "no scenario record"
    enabled = config_value(config, "unevenness.defect.enabled")
    if enabled is False:
        return None, "the defect is disabled (unevenness.defect.enabled: false)"
    x = config_number(config, "unevenness.defect.position_m")
    if x is None:
        return None, "no unevenness.defect.position_m in the scenario record"
    return x, None


def crossing_times_s(t, x, x0):
    """Per wheel (column of x), the first time its position passes x0, linear between samples; None if never."""
    times = []
    for w in range(x.shape[1]):
        d = x[:, w] - x0
        if len(d) and d[0] == 0.0:
            times.append(float(t[0]))
            continue
        k = np.nonzero(np.signbit(d[:-1]) != np.signbit(d[1:]))[0]
        if not len(k):
            times.append(None)
            continue
        k = int(k[0])
        times.append(float(t[k] + (t[k + 1] - t[k]) * (-d[k]) / (d[k + 1] - d[k])))
    return times


def impact_times_s(t, f, x, config):
    """Each wheel's time on the defect (its crossing of the defect position) and how it was found."""
    x0, why_not = defect_position_m(config)
    if x0 is not None:
        return crossing_times_s(t, x, x0), f"each wheel's crossing of the defect at x = {x0:g} m " \
                                           f"(unevenness.defect.position_m)", x0
    # Without the defect's position: the largest deviation from the static load (the first sample).
    times = [float(t[int(np.argmax(np.abs(f[:, w] - f[0, w])))]) for w in range(f.shape[1])]
    return times, f"the defect position is not known ({why_not}): each wheel's time of largest force deviation " \
                  f"from its static load", None


def house_extent_y_m(config, points, pos):
    """The house's footprint across the track (y range, m, frame track) and where it comes from."""
    gauge = config_number(config, "site.rail_gauge_m")
    distance = config_number(config, "site.building.front_wall_distance_from_rail_m")
    width = config_number(config, "building.width_m")
    if gauge is not None and distance is not None and width is not None:
        # The front wall's outer face stands the given distance from the exterior rail (site.building).
        y0 = 0.5 * gauge + distance
        return (y0, y0 + width), "site.building and building.width_m of the scenario record"
    if points:
        footprint = [p[1] for n, p in zip(points, pos) if n.startswith("footprint_")]
        if footprint:
            return (min(footprint), max(footprint)), "the footprint receivers (foundation wall mid-lines)"
    return None, None


def wave_window_s(t, y, field, first_impact_s):
    """The zoom of the wave-field figure: around the first axle's impact, else where the near field's energy is."""
    t_end = float(t[-1]) if len(t) else 0.0
    if t_end <= WAVE_WINDOW_S:
        return (0.0, t_end), "the whole record"
    if first_impact_s is not None:
        start, why = first_impact_s - WAVE_WINDOW_LEAD_S, "from just before the first axle's impact on the defect"
    else:
        near = field[y >= NEAR_FIELD_Y_M] if np.any(y >= NEAR_FIELD_Y_M) else field
        energy = np.sum(near ** 2, axis=0)
        start = float(t[int(np.argmax(energy))]) - WAVE_WINDOW_S / 3
        why = "around the near receivers' largest energy"
    start = min(max(start, 0.0), t_end - WAVE_WINDOW_S)
    return (start, start + WAVE_WINDOW_S), why


# ------------------------------------------------------------------ figures
def contact_forces_figure(t, f, wheel, impacts, impact_how, outdir):
    nw = f.shape[1]
    zoom = [w for w in range(nw) if impacts[w] is not None]
    fig, axes = plt.subplots(1, 2 if zoom else 1, figsize=(14 if zoom else 9, 4.2), squeeze=False,
                             gridspec_kw={"width_ratios": [1.6, 1]} if zoom else None)
    ax = axes[0][0]
    for w in range(nw):
        ax.plot(t, f[:, w] / 1e3, lw=0.7, color=f"C{w % 10}", label=f"wheel {w}: {wheel[w]}")
        if impacts[w] is not None:
            ax.axvline(impacts[w], color=f"C{w % 10}", ls=":", lw=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("contact force [kN]")
    ax.set_title("Wheel/rail contact forces (wheel 0 = front axle; dotted: on the defect)", fontsize=10)
    ax.legend(fontsize=7, ncol=3)
    ax.grid(alpha=0.3)
    if zoom:
        ax = axes[0][1]
        dt = t[1] - t[0] if len(t) > 1 else 1.0
        for w in zoom:
            k = (t >= impacts[w] + IMPACT_ZOOM_S[0] - dt) & (t <= impacts[w] + IMPACT_ZOOM_S[1] + dt)
            ax.plot((t[k] - impacts[w]) * 1e3, f[k, w] / 1e3, lw=0.8, color=f"C{w % 10}",
                    label=f"{wheel[w]} at {impacts[w]:.3f} s")
        ax.axvline(0.0, color="k", ls=":", lw=0.8)
        ax.set_xlim(IMPACT_ZOOM_S[0] * 1e3, IMPACT_ZOOM_S[1] * 1e3)
        ax.set_xlabel("time after the wheel reaches the defect [ms]")
        ax.set_ylabel("contact force [kN]")
        ax.set_title("Zoom on the impacts", fontsize=10)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.text(0.01, 0.01, "impact times: " + impact_how, fontsize=7)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(outdir / "contact_forces.png", dpi=120)
    plt.close(fig)


def kbf_axes(ax, kbf, components, a_u, a_o, impacts):
    """KB_F(t) of the plotted components, the A_u / A_o lines and the impact times, on a log scale
    (A_o is 20 x A_u by day: on a linear scale the curve would shrink to the bottom)."""
    peak = 0.0
    for c in components:
        kb = np.asarray(kbf[f"kb_f_{COMPONENTS[c]}"], dtype=float)
        peak = max(peak, float(np.nanmax(kb)) if kb.size else 0.0)
        ax.plot(kbf["t_s"], np.where(kb > 0, kb, np.nan), lw=0.8, color=COMPONENT_COLOURS[c],
                label=f"KB_F of {COMPONENTS[c]}")
    for value, name, style in ((a_u, "A_u", "--"), (a_o, "A_o", "-.")):
        if value is not None:
            ax.axhline(value, color="k" if name == "A_o" else "0.35", ls=style, lw=1.0, label=f"{name} = {value:g}")
    for ti in impacts:
        if ti is not None:
            ax.axvline(ti, color="0.5", ls=":", lw=0.7)
    top = max(peak, a_o or 0.0, a_u or 0.0)
    if top > 0:
        ax.set_yscale("log")
        bottom = min(x for x in (peak * 0.05 if peak > 0 else None, (a_u or top) / 30.0) if x)
        ax.set_ylim(bottom, top * 1.6)
    ax.set_xlabel("time [s] (dotted: axles on the defect)")
    ax.set_ylabel("KB_F(t) [-] (log)")
    ax.set_title("DIN 4150-2 KB_F", fontsize=9)
    ax.legend(fontsize=6, loc="lower right")


def measured_report(args):
    """A measured record alone (./railvib import's velocity CSV): its metrics and the standards that
    apply where it was measured (--kind), with the figures of a run's sensors."""
    import types
    import measured_record
    path = pathlib.Path(args.bag)
    kind = args.kind or "foundation"
    if verdicts.kind_value(kind) is None:
        die(f"--kind {kind}: one of {', '.join(verdicts.kind_names())}")
    if args.period not in (None, "day", "night"):
        die(f"--period {args.period}: day or night")
    try:
        axes, v, rate = measured_record.velocity_axes(path, args.axes.split(",") if args.axes else None)
    except measured_record.RecordError as e:
        die(f"{e} (a measured record is the velocity CSV of ./railvib import)")
    outdir = pathlib.Path(args.outdir) if args.outdir else path.with_name(path.stem + "_report")
    try:
        output_dir(outdir)
    except OutputDirError as e:
        die(str(e))
    name = path.stem
    t = np.arange(len(v)) / rate
    period = args.period or "day"
    exposure_s = args.exposure_s if args.exposure_s is not None else len(v) / rate
    summary, kbf = metrics(t, v, outdir, name, exposure_s=exposure_s, period=period, kind=kind)
    d2, d3 = summary["din4150_2"], summary["din4150_3"]
    governing = next(c for c, comp in enumerate(d3["components"]) if comp["column"] == d3["governing_component"])
    measured = [c for c in range(3) if axes[c] != "-"]
    plotted = [2] + ([governing] if governing != 2 else [])
    figures = ["sensors.png", "standards.png"]
    fig, ax = plt.subplots(1, 3, figsize=(14, 3.2), squeeze=False)
    for c in plotted:
        ax[0][0].plot(t, v[:, c] * 1e3, lw=0.6, color=COMPONENT_COLOURS[c], label=COMPONENTS[c])
        fr, amp = spectrum(t, v[:, c] * 1e3)
        ax[0][1].plot(fr, amp, lw=0.7, color=COMPONENT_COLOURS[c], label=COMPONENTS[c])
    ax[0][0].set_title(f"{name}: velocity (measured)", fontsize=9)
    ax[0][0].set_xlabel("time [s] from the record's start")
    ax[0][0].set_ylabel("v [mm/s]")
    ax[0][0].legend(fontsize=6, loc="upper right")
    spectrum_axes(ax[0][1], spectrum_range_hz(rate), None, "z" if governing == 2 else None)
    ax[0][1].set_title("Fourier transform magnitude (rectangular window)", fontsize=9)
    ax[0][1].legend(fontsize=6, loc="upper right")
    kbf_axes(ax[0][2], kbf, plotted, d2["a_u"], d2["a_o"], [])
    ax[0][2].set_xlabel("time [s]")
    for a in ax[0]:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(outdir / "sensors.png", dpi=110)
    plt.close(fig)
    # The standards figure as for a run's sensor: the kind stands where a live sensor's message would.
    stand_in = types.SimpleNamespace(kind=verdicts.kind_value(kind))
    standards = standards_figure([name], {name: stand_in}, {name: summary}, None, outdir / "standards.png")
    provenance = path.with_suffix(".json")
    source = json.loads(provenance.read_text()) if provenance.exists() else None
    lines = [f"# railvib report: the measured record `{path.name}`", "",
             f"- record: {len(v)} samples at {rate:g} Hz ({len(v) / rate:g} s); channels {', '.join(axes)} as "
             "x, y, z of frame track" + ("" if len(measured) == 3 else
                                        " ('-': not measured, taken as zero: the vector PPV and the governing "
                                        "component cover the measured axes only)"),
             "- imported by `./railvib import` from " + (f"`{source.get('source')}` ({source.get('quantity')}, "
                                                         f"{source.get('unit')})" if isinstance(source, dict)
                                                         else "(no provenance file beside the record)"),
             f"- where it was measured: {kind} (--kind; the standards judged follow from it, docs/signal.md)",
             "- no model resolution applies: every verdict is assessable", "",
             "## Metrics and standards", "",
             "| kind | KB_Fmax | PPV, vector [mm/s] | governing component: peak [mm/s] | its frequency [Hz] | "
             "its DIN 4150-3 limit [mm/s] | DIN 4150-2 | DIN 4150-3 |", "|---|---|---|---|---|---|---|---|"]
    g = d3["components"][governing]
    limit = g.get("din4150_3_limit_mm_s")
    lines.append(f"| {kind} | {d2['kb_fmax']:.4f} | {d3['vector_peak_mm_s']:.4f} | {COMPONENTS[governing]} "
                 f"{g['ppv_mm_s']:.4f} | {g['dominant_frequency_hz']:.1f} | "
                 f"{limit if limit is None else format(limit, '.1f')} | {d2['level']} ({d2['reason']}) | "
                 f"{d3['level']} |")
    lines += ["", f"DIN 4150-2 ({period}): KB_FTr {d2['kb_ftr']:.3g} over T_e = {exposure_s:g} s, A_u / A_o / A_r "
              f"{d2['a_u']:g} / {d2['a_o']:g} / {d2['a_r']:g}. DIN 4150-3: {d3['building']}. From `railvib_tool "
              f"metrics` on the record (`{name}_velocity.csv` here), the core's code the live sensors use; in the "
              "free field neither standard applies and the figures are for information.", "",
              "![sensors](sensors.png)", "", "![standards](standards.png)", ""]
    (outdir / "report.md").write_text("\n".join(lines))
    (outdir / "report.json").write_text(json.dumps(
        {"record": str(path), "kind": kind, "axes": axes, "rate_hz": rate, "figures": figures,
         "metrics": summary, "standards": standards}, indent=1, default=str))
    print(f"railvib report: {outdir / 'report.md'} ({len(figures)} figures)")
    return 0


def main(argv):
    parser = argparse.ArgumentParser(prog="./railvib report", description=__doc__.split("\n")[0])
    parser.add_argument("bag")
    parser.add_argument("outdir", nargs="?")
    parser.add_argument("--exposure-s", type=float, default=None,
                        help="DIN 4150-2 exposure time for KB_FTr (s); default: the record length (one passage)")
    parser.add_argument("--kind", help="a measured record: where it was measured (free_field, foundation, floor)")
    parser.add_argument("--axes", help="a measured record: its channels as x,y,z ('-': not measured)")
    parser.add_argument("--period", help="a measured record: the DIN 4150-2 period (day, night)")
    parser.error = lambda message: die(f"{message}\nusage: {USAGE}")
    if len(argv) < 2:
        die("usage: " + USAGE)
    args = parser.parse_args(argv[1:])
    if args.exposure_s is not None and not (args.exposure_s > 0 and np.isfinite(args.exposure_s)):
        die(f"--exposure-s {args.exposure_s}: must be a positive number of seconds")
    if args.bag.lower().endswith(".csv"):
        return measured_report(args)
    for option in ("kind", "axes", "period"):
        if getattr(args, option) is not None:
            die(f"--{option} is for a measured record (a .csv); a bag's sensors say their own")
    bag_path = pathlib.Path(args.bag)
    if not bag_path.exists():
        die(f"no such bag: {bag_path}")
    outdir = pathlib.Path(args.outdir) if args.outdir else bag_path.with_name(bag_path.stem + "_report")
    # Every expected stream, its type and its blocks first (scripts/bag_check.py): a foreign or
    # malformed bag is refused here; an incomplete one is reported, then drawn as far as it goes.
    checked = bag_check.check_bag(bag_path)
    if checked.refused:
        die(checked.refused)
    for finding in checked.findings:
        print("railvib report: " + finding, file=sys.stderr)
    INCOMPLETE.extend(checked.incomplete)
    try:
        output_dir(outdir)
    except OutputDirError as e:
        die(str(e))
    try:
        bag = rosbag.Bag(str(bag_path))
    except Exception as e:  # rosbag raises several types for truncated or corrupt files
        die(f"cannot read {bag_path}: {e}")

    lines = [f"# railvib report: `{bag_path.name}`", ""]
    figures = []
    shown = {"bag": str(bag_path), "figures": figures}  # report.json: what the figures show

    with bag:
        topics = bag.get_type_and_topic_info().topics
        record, why_not = scenario_record(bag)
        config = record.get("config") if record and isinstance(record.get("config"), dict) else None
        shown["scenario_recorded"] = record is not None
        lines += scenario_section(record, why_not, outdir)
        mesh_f_max_hz = config_number(config, "soil.mesh.f_max_hz")

        cf = read_stream(bag, names.CONTACT_FORCES)
        ss = read_stream(bag, names.SENSOR_SAMPLES)
        sv = read_stream(bag, names.SURFACE_VELOCITIES)
        rates = [s[0].sample_period_s for s in (ss, sv) if s]
        f_max_hz = spectrum_range_hz(*[1.0 / p for p in rates])
        shown["spectrum"] = {"definition": "dt |FFT(v)|, rectangular window over the whole record",
                             "unit": "(mm/s)/Hz", "range_hz": [0.0, f_max_hz], "mesh_f_max_hz": mesh_f_max_hz}

        # ---- contact forces around the defect
        impacts = []
        if cf:
            nw = cf[0].wheel_count
            f = stacked(cf, "force_n", nw)
            x = stacked(cf, "position_m", nw)
            t = np.arange(len(f)) * cf[0].sample_period_s
            wheel_rail = list(cf[0].wheel_rail)
            wheel, wheel_how = wheel_names(config, nw, wheel_rail)
            impacts, impact_how, x_defect = impact_times_s(t, f, x, config)
            if len(wheel_rail) == nw and x_defect is not None:
                # a wheel on a rail without the pad passes the defect's position but meets no pad
                on_pad = defect_rails(config)
                impacts = [ti if wheel_rail[w] in on_pad else None for w, ti in enumerate(impacts)]
            contact_forces_figure(t, f, wheel, impacts, impact_how, outdir)
            figures.append("contact_forces.png")
            shown["contact_forces"] = {"wheel_names": wheel, "impact_times_s": impacts, "impact_source": impact_how,
                                       "defect_position_m": x_defect}
            lines += ["## Contact forces", "",
                      f"Wheel 0 is the front axle; names: {wheel_how}. Impact times: {impact_how}"
                      + (" (the force rises a little earlier: a wheel of radius R meets a pad of height h about "
                         "sqrt(2 R h) before its contact point is over it)." if x_defect is not None else "."), "",
                      "| wheel | axle | static [kN] | min [kN] | max [kN] | on the defect at [s] |",
                      "|---|---|---|---|---|---|"]
            for w in range(nw):
                at = f"{impacts[w]:.4f}" if impacts[w] is not None else (
                    "no pad on its rail" if len(wheel_rail) == nw and x_defect is not None
                    and wheel_rail[w] not in defect_rails(config) else "not in the record")
                lines.append(f"| {w} | {wheel[w]} | {f[0, w] / 1e3:.2f} | {f[:, w].min() / 1e3:.2f} | "
                             f"{f[:, w].max() / 1e3:.2f} | {at} |")
            lines.append("")
        first_impact = min([ti for ti in impacts if ti is not None], default=None)

        # ---- virtual sensors: time history, spectrum, KB_F + metric table
        live = last_metrics(bag)
        if ss:
            sensor_names = names_in_order(ss, live)
            ns = len(sensor_names)
            v = stacked(ss, "velocity_m_s", ns, 3)
            fs_s = 1.0 / ss[0].sample_period_s
            t = np.arange(len(v)) * ss[0].sample_period_s
            record_s = len(v) / fs_s
            exposure_s = args.exposure_s if args.exposure_s is not None else record_s
            period, period_how = din_period(config, live)
            shown["sensors"] = {}
            rated = {}
            summaries = {}
            fig, axes = plt.subplots(ns, 3, figsize=(14, 2.9 * ns), squeeze=False)
            for i, name in enumerate(sensor_names):
                m = live[name]
                summary, kbf = metrics(t, v[:, i, :], outdir, name, exposure_s=exposure_s, period=period,
                                       kind=sensor_kind(m), resolved_hz=getattr(m, "resolved_hz", None))
                rated[name] = summary["din4150_2"]
                summaries[name] = summary
                governing = int(m.governing_component) if m.governing_component in (0, 1, 2) else 2
                plotted = [2] + ([governing] if governing != 2 else [])
                a_u, a_o, guide_how = guide_values(m, period)
                ax = axes[i][0]
                for c in plotted:
                    ax.plot(t, v[:, i, c] * 1e3, lw=0.6, color=COMPONENT_COLOURS[c], label=COMPONENTS[c])
                for ti in impacts:
                    if ti is not None:
                        ax.axvline(ti, color="0.5", ls=":", lw=0.7)
                ax.set_title(f"{name}: velocity" + ("" if governing == 2 else
                                                    f" ({COMPONENTS[governing]} governs DIN 4150-3)"), fontsize=9)
                ax.set_xlabel("time [s] (dotted: axles on the defect)")
                ax.set_ylabel("v [mm/s]")
                ax.legend(fontsize=6, loc="upper right")
                ax = axes[i][1]
                for c in plotted:
                    fr, amp = spectrum(t, v[:, i, c] * 1e3)
                    ax.plot(fr, amp, lw=0.7, color=COMPONENT_COLOURS[c], label=COMPONENTS[c])
                spectrum_axes(ax, f_max_hz, mesh_f_max_hz, "z" if governing == 2 else None)
                ax.set_title("Fourier transform magnitude (rectangular window)", fontsize=9)
                ax.legend(fontsize=6, loc="upper right")
                kbf_axes(axes[i][2], kbf, plotted, a_u, a_o, impacts)
                for a in axes[i]:
                    a.grid(alpha=0.3)
                shown["sensors"][name] = {"a_u": a_u, "a_o": a_o, "guide_source": guide_how, "period": period,
                                          "governing_component": COMPONENTS[governing],
                                          "plotted_components": [COMPONENTS[c] for c in plotted],
                                          "kb_ftr": rated[name]["kb_ftr"], "exposure_s": rated[name]["exposure_s"],
                                          "rated_verdict": rated[name]["verdict"], "reason": rated[name]["reason"]}
            fig.tight_layout()
            fig.savefig(outdir / "sensors.png", dpi=110)
            plt.close(fig)
            figures.append("sensors.png")
            shown["standards"] = standards_figure(sensor_names, live, summaries, mesh_f_max_hz,
                                                  outdir / "standards.png")
            figures.append("standards.png")
            lines += ["## Virtual sensors", "",
                      "| sensor | kind | KB_Fmax | PPV, vector [mm/s] | governing component: peak [mm/s] | "
                      "its frequency [Hz] | its DIN 4150-3 limit [mm/s] | DIN 4150-2 | DIN 4150-3 |",
                      "|---|---|---|---|---|---|---|---|---|"]
            for name in sensor_names:
                m = live[name]
                lines.append("| {} | {} | {:.4f} | {:.4f} | {} {:.4f} | {:.1f} | {:.1f} | {} | {} |".format(
                    name, sensor_kind(m) or "not recorded", m.kb_f_max, m.ppv_m_s * 1e3, COMPONENTS[m.governing_component],
                    m.governing_ppv_m_s * 1e3, m.dominant_frequency_hz, m.din4150_3_limit_m_s * 1e3,
                    verdict_text(m.din4150_2_verdict), verdict_text(m.din4150_3_verdict)))
            resolved = sorted({m.resolved_hz for m in live.values() if getattr(m, "resolved_hz", 0.0) > 0})
            lines += ["", "The standards apply where the sensor stands: DIN 4150-2 (people) and DIN 4150-3 "
                      "(structures) in and on buildings, not in the free field (\"not applicable\": the figures "
                      "are for information). DIN 4150-3 (short-term, residential building) compares the peak of "
                      "each velocity component with its guide value: at the foundation the Table 1 curve at that "
                      "component's dominant frequency, on a floor 15 mm/s horizontal and 20 mm/s vertical; the "
                      "vector PPV (peak of |v|) is given for information. DIN 4150-2 compares KB_Fmax with the "
                      "A_u / A_o guide values of the chosen period. A verdict whose governing frequency lies above "
                      "the model's resolved frequency (" + (", ".join(f"{f:g} Hz" for f in resolved) or "not recorded")
                      + ", soil.mesh.f_max_hz) is \"not assessable\". Values and verdicts as the live sensors "
                      "recorded them (" + names.SENSOR_METRICS + ").", ""]
            not_z = [f"{n}: {shown['sensors'][n]['governing_component']}" for n in sensor_names
                     if shown["sensors"][n]["governing_component"] != "vz"]
            if not_z:
                lines += ["The sensors figure plots v_z and, where another component governs DIN 4150-3, that one "
                          "too (its time history, spectrum and KB_F): " + ", ".join(not_z) + ".", ""]
            lines += ["### DIN 4150-2 exposure", "",
                      f"Rating KB_FTr over an exposure of T_e = {exposure_s:g} s "
                      + ("(the record length)" if args.exposure_s is None else "(--exposure-s)")
                      + f" within the {period}'s rating period (period: {period_how}), from `railvib_tool metrics "
                      f"--exposure-s {exposure_s:g} --period {period}` on the recorded samples "
                      f"(`<sensor>_velocity.csv` here; rerun it with the exposure of N passages, N x {record_s:g} s).",
                      "", "| sensor | KB_Fmax (live) | live verdict | KB_FTr | T_e [s] | A_r | rated verdict |",
                      "|---|---|---|---|---|---|---|"]
            disagree = []
            for name in sensor_names:
                m, r = live[name], rated[name]
                lines.append(f"| {name} | {m.kb_f_max:.4f} | {verdict_text(m.din4150_2_verdict)} | {r['kb_ftr']:.3g} | "
                             f"{r['exposure_s']:g} | {r['a_r']:g} | {r['verdict']} ({r['reason']}) |")
                expected = next((code for text, code in _LIVE_OF_REASON if r["reason"].startswith(text)), None)
                if expected is not None and verdicts.judged(m.din4150_2_verdict) and expected != m.din4150_2_verdict:
                    disagree.append(f"{name} (live KB_Fmax {m.kb_f_max:.4f}, recorded samples' {r['kb_fmax']:.4f})")
            lines += ["", "The live verdict judges KB_Fmax alone (OK up to A_u, ERROR above A_o, WARN in between, "
                      "where DIN 4150-2 lets the rating decide); the rated verdict makes the same KB_Fmax test and "
                      "only decides the WARN case, by KB_FTr <= A_r over the stated exposure, so an OK or an ERROR "
                      "is the same in both and a WARN becomes met or not met.", ""]
            if disagree:
                lines += ["Note: for " + ", ".join(disagree) + " the KB_Fmax of the recorded samples and the live "
                          "sensor's last message fall on different sides of a guide value.", ""]
            guides = sorted({(s["a_u"], s["a_o"], s["guide_source"]) for s in shown["sensors"].values()},
                            key=lambda g: str(g))
            lines += ["KB_F plots: A_u / A_o lines " + "; ".join(
                f"{a_u:g} / {a_o:g} from {how}" if a_u is not None else how for a_u, a_o, how in guides) + ".", ""]

        # ---- wave field along the line perpendicular to the track (receivers named line_y*)
        points, pos = layout(bag, names.SURFACE_POINTS)
        if sv and points:
            nr = sv[0].receiver_count
            vel = stacked(sv, "velocity_m_s", nr, 3)
            t = np.arange(len(vel)) * sv[0].sample_period_s
            line = [(pos[i][1], i) for i, n in enumerate(points) if n.startswith(names.RECEIVER_LINE_PREFIX)]
            if line and len(t):
                line.sort()
                y = np.array([p for p, _ in line])
                field = np.array([vel[:, i, 2] for _, i in line]) * 1e3
                window, window_how = wave_window_s(t, y, field, first_impact)
                house, house_how = house_extent_y_m(config, points, pos)
                house_in_run = names.BUILDING_POINTS in topics or names.BUILDING_RESPONSE in topics
                k = (t >= window[0]) & (t <= window[1])
                # A record no longer than the zoom is drawn once; a longer one also whole, below the zoom.
                zoomed = window[0] > t[0] or window[1] < t[-1]
                if zoomed:
                    fig, axes = plt.subplots(2, 1, figsize=(10, 7.5), gridspec_kw={"height_ratios": [3, 1]},
                                             constrained_layout=True)
                else:
                    fig, ax = plt.subplots(figsize=(10, 5.8), constrained_layout=True)
                    axes = [ax]
                # Colour scale from the points off the sleeper footprint (y >= 2 m) in the zoom, where
                # the field propagates; points under the sleeper ends would saturate it.
                off = field[y >= NEAR_FIELD_Y_M][:, k] if np.any(y >= NEAR_FIELD_Y_M) else field[:, k]
                lim = float(np.percentile(np.abs(off), 99.9)) if off.size else 0.0
                lim = lim or 1.0
                for ax, cols in zip(axes, (k, slice(None))):
                    im = ax.pcolormesh(t[cols], y, field[:, cols], cmap="RdBu_r", vmin=-lim, vmax=lim, shading="auto")
                    if house:
                        style = "-" if house_in_run else "--"
                        for edge in house:
                            ax.axhline(edge, color="k", ls=style, lw=1.0)
                    if first_impact is not None:
                        ax.axvline(first_impact, color="k", ls=":", lw=0.8)
                    ax.set_ylabel("distance from the\ntrack axis [m]")
                if house:
                    label = "house" if house_in_run else "house site\n(not in this run)"
                    axes[0].text(0.01, 0.5 * (house[0] + house[1]), label, va="center", fontsize=8,
                                 transform=blended_transform_factory(axes[0].transAxes, axes[0].transData),
                                 bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8})
                axes[0].set_title("Wave field along the line perpendicular to the track, in front of the defect"
                                  + (f": {window[0]:.2f}-{window[1]:.2f} s" if zoomed else ""), fontsize=10)
                if zoomed:
                    axes[0].set_xlabel("time [s]")
                    axes[1].axvspan(window[0], window[1], facecolor="none", edgecolor="k", lw=1.2)
                    axes[1].set_title("the whole record (box: the zoom above)", fontsize=8)
                fig.colorbar(im, ax=axes, label="vertical velocity [mm/s]")
                # The legend of the marks, under the lowest panel (constrained layout keeps it in the figure).
                axes[-1].set_xlabel("time [s]\n" + (f"zoom: {window_how}" if zoomed else "the whole record")
                                    + ("; dotted: the first axle on the defect" if first_impact is not None else "")
                                    + (f"\nlines: the house's footprint ({house_how})" if house
                                       else "\nhouse placement not known"), fontsize=8)
                fig.savefig(outdir / "wave_field.png", dpi=120)
                plt.close(fig)
                figures.append("wave_field.png")
                shown["wave_field"] = {"window_s": list(window), "window_source": window_how,
                                       "house_y_m": list(house) if house else None, "house_source": house_how,
                                       "house_in_run": house_in_run}

        # ---- house floors vs the free field at the same place (paper Fig. 15)
        free_field_point = names.BUILDING_RESPONSE_FREE_FIELD_POINT
        if ss and sv and points and free_field_point in points:
            snames = list(ss[0].sensor_names)
            floors = [n for n in ("house_ground_floor", "house_first_floor") if n in snames]
            if floors:
                # With two-way coupling the soil at the response point is the foundation, not the free field:
                # that comes from the one_way run (./railvib compare FREE.bag THIS.bag).
                two_way = config_coupling(config) == "two_way"
                soil_label = "soil there (two-way: the foundation)" if two_way else "free field (no house)"
                vs, vf = v, vel  # the sensor and receiver records stacked above
                ts = np.arange(len(vs)) * ss[0].sample_period_s
                tf = np.arange(len(vf)) * sv[0].sample_period_s
                free = vf[:, points.index(free_field_point), 2] * 1e3
                fig, axes = plt.subplots(len(floors), 2, figsize=(12, 3.2 * len(floors)), squeeze=False)
                for row, name in enumerate(floors):
                    house_v = vs[:, snames.index(name), 2] * 1e3
                    ax = axes[row][0]
                    ax.plot(ts, house_v, lw=0.7, label=name)
                    ax.plot(tf, free, "r--", lw=0.6, label=soil_label)
                    ax.set_xlabel("time [s]")
                    ax.set_ylabel("v_z [mm/s]")
                    ax.legend(fontsize=8)
                    ax = axes[row][1]
                    for t_, x_, style, label in ((ts, house_v, "-", name), (tf, free, "r--", soil_label)):
                        fr, amp = spectrum(t_, x_)
                        ax.plot(fr, amp, style, lw=0.7, label=label)
                    spectrum_axes(ax, f_max_hz, mesh_f_max_hz)
                    ax.legend(fontsize=8)
                    for a in axes[row]:
                        a.grid(alpha=0.3)
                railvib_plots.fit_title(fig, "House response points (mid-width, 3/4 length) vs the soil under them "
                                        "(two-way; the free field is the one_way run: ./railvib compare FREE.bag "
                                        "THIS.bag)" if two_way else
                                        "House response points (mid-width, 3/4 length) vs the free field there")
                fig.tight_layout()
                fig.savefig(outdir / "building_vs_free_field.png", dpi=110)
                plt.close(fig)
                figures.append("building_vs_free_field.png")

    lines += ["## Figures", ""]
    if any(f in figures for f in ("sensors.png", "building_vs_free_field.png")):
        mesh = (f"the dotted line marks the frequency the soil mesh resolves (soil.mesh.f_max_hz = "
                f"{mesh_f_max_hz:g} Hz): above it (shaded) the results are not trustworthy"
                if mesh_f_max_hz is not None else "the soil mesh's resolved frequency is not known (no scenario "
                                                  "record): it is not marked")
        lines += [f"Spectra: the magnitude of the Fourier transform of the whole record, |V(f)| = dt |FFT(v)| "
                  f"with a rectangular window, in (mm/s)/Hz (a passage is a transient: its spectrum is a density, "
                  f"not the amplitude of a steady sine; a sine of amplitude A lasting T gives A T/2). Every spectrum "
                  f"spans 0-{f_max_hz:g} Hz; {mesh}.", ""]
    if "standards.png" in figures:
        lines += ["Standards (`standards.png`, drawn as the live monitor draws them): per sensor the one-third "
                  "octave levels of v_x, v_y, v_z over the record (dB re 1e-9 m/s, ISO 1683; bands above the "
                  "resolved frequency shaded) and each component's peak at its dominant frequency against the "
                  "DIN 4150-3 guideline where the sensor stands: the foundation curve (Table 1, row 2), on a floor "
                  "15 mm/s horizontal and 20 mm/s vertical, in the free field none (the curve grey, for scale).", ""]
    if "wave_field.png" in figures:
        wf = shown["wave_field"]
        span = (f"{wf['window_s'][0]:.2f}-{wf['window_s'][1]:.2f} s ({wf['window_source']}), the whole record below"
                if wf["window_source"] != "the whole record" else "the whole record (no longer than the zoom)")
        lines += [f"Wave field: {span}; " + (f"the lines mark the house's footprint, y = {wf['house_y_m'][0]:.2f}-"
                                       f"{wf['house_y_m'][1]:.2f} m ({wf['house_source']})."
                                       if wf["house_y_m"] else "the house's placement is not known."), ""]
    lines += [f"![{f}]({f})" for f in figures]
    if INCOMPLETE:
        lines.insert(2, "**Incomplete run**: these streams stop before their end: " + ", ".join(INCOMPLETE) + "\n")
    (outdir / "report.md").write_text("\n".join(lines) + "\n")
    (outdir / "report.json").write_text(json.dumps(shown, indent=1) + "\n")
    print(f"railvib report: {outdir / 'report.md'} ({len(figures)} figures)")
    if INCOMPLETE:
        print("railvib report: incomplete run, streams stopped early: " + ", ".join(INCOMPLETE), file=sys.stderr)
        return 1
    return 1 if checked.code else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
