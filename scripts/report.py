#!/usr/bin/env python3
"""railvib report: figures and a Markdown summary from a recorded scenario bag.

usage: ./railvib report BAG [OUTDIR]

Reads the railvib streams of the bag (whatever the scenario recorded):
  /contact_forces      contact forces at the defect
  /soil_loads          ballast-to-soil loads
  /surface_velocities  soil receivers (+ /surface_points names)
  /building_response   house response points (+ /building_points names)
  /sensor_samples      virtual sensors
  /sensor_metrics      the sensors' metrics and verdicts (the last message of each)
and writes PNG figures plus report.md into OUTDIR (default: BAG without
.bag + "_report"). The metric table (KB_Fmax, PPV, the governing component,
DIN 4150 verdicts) is what the live sensors recorded in the bag; the KB_F(t)
curves come from `railvib_tool metrics` on the recorded samples: the same core
code, never re-implemented here.
"""
import csv
import json
import os
import pathlib
import subprocess
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import bag_check  # noqa: E402
import railvib_names as names  # noqa: E402
from railvib_paths import find_railvib_tool  # noqa: E402

try:
    import rosbag
except ImportError:  # pragma: no cover
    sys.exit("railvib report: python3-rosbag is required (./railvib setup installs it)")


INCOMPLETE = []  # streams whose last block is not flagged end_of_stream (the run stopped early)


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


VERDICTS = {0: "OK", 1: "WARN (rating KB_FTr decides)", 2: "ERROR"}
COMPONENTS = ["vx", "vy", "vz"]  # the columns railvib_tool metrics names them by


def last_metrics(bag):
    """The last VibrationMetrics of each sensor (it covers the whole record)."""
    last = {}
    for _, m, _ in bag.read_messages(topics=[names.SENSOR_METRICS]):
        last[m.sensor_name] = m
    return last


def metrics(t, v_m_s, outdir, name):
    """Run railvib_tool metrics on one sensor's 3 components; returns its JSON summary and KB_F(t)."""
    path = outdir / f"{name}_velocity.csv"
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["t_s", "vx", "vy", "vz"])
        for i in range(len(t)):
            w.writerow([repr(t[i])] + [repr(x) for x in v_m_s[i]])
    out = subprocess.run(
        tool() + ["metrics", "--csv", str(path), "--column", "vx,vy,vz", "--out", str(outdir / f"{name}_kbf.csv")],
        capture_output=True, text=True)
    if out.returncode != 0:
        die(f"railvib_tool metrics failed for {name}: {out.stderr.strip()}")
    kbf = np.genfromtxt(outdir / f"{name}_kbf.csv", delimiter=",", names=True)
    return json.loads(out.stdout), kbf


def names_in_order(ss, live):
    """Sensors in the order of the samples stream; each must have its recorded metrics."""
    order = list(ss[0].sensor_names)
    missing = [n for n in order if n not in live]
    if missing:
        die("no metrics recorded on " + names.SENSOR_METRICS + " for " + ", ".join(missing))
    return order


def spectrum(t, x):
    n = len(x)
    if n < 2:
        return np.array([0.0]), np.array([0.0])
    dt = t[1] - t[0]
    win = np.hanning(n)
    amp = np.abs(np.fft.rfft(x * win)) * 2.0 / win.sum()
    return np.fft.rfftfreq(n, dt), amp


def main(argv):
    if len(argv) < 2:
        die("usage: ./railvib report BAG [OUTDIR]")
    bag_path = pathlib.Path(argv[1])
    if not bag_path.exists():
        die(f"no such bag: {bag_path}")
    outdir = pathlib.Path(argv[2]) if len(argv) > 2 else bag_path.with_name(bag_path.stem + "_report")
    # Every expected stream, its type and its blocks first (scripts/bag_check.py): a foreign or
    # malformed bag is refused here; an incomplete one is reported, then drawn as far as it goes.
    checked = bag_check.check_bag(bag_path)
    if checked.refused:
        die(checked.refused)
    for finding in checked.findings:
        print("railvib report: " + finding, file=sys.stderr)
    INCOMPLETE.extend(checked.incomplete)
    outdir.mkdir(parents=True, exist_ok=True)
    try:
        bag = rosbag.Bag(str(bag_path))
    except Exception as e:  # rosbag raises several types for truncated or corrupt files
        die(f"cannot read {bag_path}: {e}")

    lines = [f"# railvib report: `{bag_path.name}`", ""]
    figures = []

    with bag:
        # ---- contact forces around the defect
        cf = read_stream(bag, names.CONTACT_FORCES)
        if cf:
            nw = cf[0].wheel_count
            f = stacked(cf, "force_n", nw)
            x = stacked(cf, "position_m", nw)
            t = np.arange(len(f)) * cf[0].sample_period_s
            fig, ax = plt.subplots(figsize=(9, 4))
            for w in range(nw):
                ax.plot(t, f[:, w] / 1e3, lw=0.7, label=f"wheel {w + 1}")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("contact force [kN]")
            ax.set_title("Wheel/rail contact forces")
            ax.legend(fontsize=7, ncol=3)
            ax.grid(alpha=0.3)
            fig.tight_layout()
            fig.savefig(outdir / "contact_forces.png", dpi=120)
            plt.close(fig)
            figures.append("contact_forces.png")
            lines += ["## Contact forces", "", "| wheel | static [kN] | min [kN] | max [kN] |", "|---|---|---|---|"]
            for w in range(nw):
                lines.append(f"| {w + 1} | {f[0, w] / 1e3:.2f} | {f[:, w].min() / 1e3:.2f} | {f[:, w].max() / 1e3:.2f} |")
            lines.append("")

        # ---- virtual sensors: time history, spectrum, KB_F + metric table
        ss = read_stream(bag, names.SENSOR_SAMPLES)
        live = last_metrics(bag)
        if ss:
            sensor_names = list(ss[0].sensor_names)
            ns = len(sensor_names)
            v = stacked(ss, "velocity_m_s", ns, 3)
            t = np.arange(len(v)) * ss[0].sample_period_s
            fig, axes = plt.subplots(ns, 3, figsize=(13, 2.6 * ns), squeeze=False)
            for i, name in enumerate(sensor_names):
                _, kbf = metrics(t, v[:, i, :], outdir, name)
                ax = axes[i][0]
                ax.plot(t, v[:, i, 2] * 1e3, lw=0.6)
                ax.set_title(f"{name}: vertical velocity")
                ax.set_xlabel("time [s]")
                ax.set_ylabel("v_z [mm/s]")
                ax = axes[i][1]
                fr, amp = spectrum(t, v[:, i, 2] * 1e3)
                ax.plot(fr, amp, lw=0.7)
                ax.set_xlim(0, 100)
                ax.set_xlabel("frequency [Hz]")
                ax.set_ylabel("|V_z| [mm/s]")
                ax.set_title("spectrum")
                ax = axes[i][2]
                cols = kbf.dtype.names
                ax.plot(kbf[cols[0]], kbf[cols[-1]], lw=0.8)
                ax.set_xlabel("time [s]")
                ax.set_ylabel("KB_F(t) (vertical) [-]")
                ax.set_title("DIN 4150-2 KB_F")
                for a in axes[i]:
                    a.grid(alpha=0.3)
            fig.tight_layout()
            fig.savefig(outdir / "sensors.png", dpi=110)
            plt.close(fig)
            figures.append("sensors.png")
            lines += ["## Virtual sensors", "",
                      "| sensor | KB_Fmax | PPV, vector [mm/s] | governing component: peak [mm/s] | "
                      "its frequency [Hz] | its DIN 4150-3 limit [mm/s] | DIN 4150-2 | DIN 4150-3 |",
                      "|---|---|---|---|---|---|---|---|"]
            for name in names_in_order(ss, live):
                m = live[name]
                lines.append("| {} | {:.4f} | {:.4f} | {} {:.4f} | {:.1f} | {:.1f} | {} | {} |".format(
                    name, m.kb_f_max, m.ppv_m_s * 1e3, COMPONENTS[m.governing_component], m.governing_ppv_m_s * 1e3,
                    m.dominant_frequency_hz, m.din4150_3_limit_m_s * 1e3, VERDICTS[m.din4150_2_verdict],
                    VERDICTS[m.din4150_3_verdict]))
            lines += ["", "DIN 4150-3 (short-term, residential building, Table 1 row 2) compares the peak of "
                      "each velocity component with the guide value at that component's dominant frequency; "
                      "the vector PPV (peak of |v|) is given for information. DIN 4150-2 compares KB_Fmax "
                      "with the A_u / A_o guide values of the chosen period (between them the rating KB_FTr "
                      "over the exposure decides: `railvib_tool metrics --exposure-s`). Values and verdicts as the "
                      "live sensors recorded them (" + names.SENSOR_METRICS + ").", ""]

        # ---- wave field along the line perpendicular to the track (receivers named line_y*)
        sv = read_stream(bag, names.SURFACE_VELOCITIES)
        points, pos = layout(bag, names.SURFACE_POINTS)
        if sv and points:
            nr = sv[0].receiver_count
            vel = stacked(sv, "velocity_m_s", nr, 3)
            t = np.arange(len(vel)) * sv[0].sample_period_s
            line = [(pos[i][1], i) for i, n in enumerate(points) if n.startswith(names.RECEIVER_LINE_PREFIX)]
            if line:
                line.sort()
                y = np.array([p for p, _ in line])
                field = np.array([vel[:, i, 2] for _, i in line]) * 1e3
                fig, ax = plt.subplots(figsize=(9, 5))
                # Colour scale from the points off the sleeper footprint (y >= 2 m), where the
                # field propagates; points under the sleeper ends would saturate it.
                off = field[y >= 2.0] if np.any(y >= 2.0) else field
                lim = float(np.percentile(np.abs(off), 99.9)) or 1.0
                im = ax.pcolormesh(t, y, field, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="auto")
                fig.colorbar(im, ax=ax, label="vertical velocity [mm/s]")
                ax.set_xlabel("time [s]")
                ax.set_ylabel("distance from the track axis [m]")
                ax.set_title("Wave field along the line perpendicular to the track, in front of the defect")
                fig.tight_layout()
                fig.savefig(outdir / "wave_field.png", dpi=120)
                plt.close(fig)
                figures.append("wave_field.png")

        # ---- house floors vs the free field at the same place (paper Fig. 15)
        free_field_point = names.BUILDING_RESPONSE_FREE_FIELD_POINT
        if ss and sv and points and free_field_point in points:
            snames = list(ss[0].sensor_names)
            floors = [n for n in ("house_ground_floor", "house_first_floor") if n in snames]
            if floors:
                vs, vf = v, vel  # the sensor and receiver records stacked above
                ts = np.arange(len(vs)) * ss[0].sample_period_s
                tf = np.arange(len(vf)) * sv[0].sample_period_s
                free = vf[:, points.index(free_field_point), 2] * 1e3
                fig, axes = plt.subplots(len(floors), 2, figsize=(12, 3.2 * len(floors)), squeeze=False)
                for row, name in enumerate(floors):
                    house = vs[:, snames.index(name), 2] * 1e3
                    ax = axes[row][0]
                    ax.plot(ts, house, lw=0.7, label=name)
                    ax.plot(tf, free, "r--", lw=0.6, label="free field (no house)")
                    ax.set_xlabel("time [s]")
                    ax.set_ylabel("v_z [mm/s]")
                    ax.legend(fontsize=8)
                    ax = axes[row][1]
                    for t_, x_, style, label in ((ts, house, "-", name), (tf, free, "r--", "free field")):
                        fr, amp = spectrum(t_, x_)
                        ax.plot(fr, amp, style, lw=0.7, label=label)
                    ax.set_xlim(0, 60)
                    ax.set_xlabel("frequency [Hz]")
                    ax.set_ylabel("|V_z| [mm/s]")
                    ax.legend(fontsize=8)
                    for a in axes[row]:
                        a.grid(alpha=0.3)
                fig.suptitle("House response points (mid-width, 3/4 length) vs the free field there")
                fig.tight_layout()
                fig.savefig(outdir / "building_vs_free_field.png", dpi=110)
                plt.close(fig)
                figures.append("building_vs_free_field.png")

    lines += ["## Figures", ""] + [f"![{f}]({f})" for f in figures]
    if INCOMPLETE:
        lines.insert(2, "**Incomplete run**: these streams stop before their end: " + ", ".join(INCOMPLETE) + "\n")
    (outdir / "report.md").write_text("\n".join(lines) + "\n")
    print(f"railvib report: {outdir / 'report.md'} ({len(figures)} figures)")
    if INCOMPLETE:
        print("railvib report: incomplete run, streams stopped early: " + ", ".join(INCOMPLETE), file=sys.stderr)
        return 1
    return 1 if checked.code else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
