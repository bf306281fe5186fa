#!/usr/bin/env python3
"""railvib mitigation: the catalogue of named measures and the insertion loss of each (issue 33).

Used by ./railvib mitigate (scripts/study.py --measure NAME ...): the scenario runs without any
measure (the baseline) and once with each named measure's configuration keys over it; from the last
VibrationMetrics of every sensor (the core's metrics: one-third octave velocity levels re 1e-9 m/s,
PPV, KB_Fmax, DIN 4150 verdicts) this module writes, per measure and receiver:

- the insertion loss per one-third octave band, ISO 14837-1: IL = L_v(without) - L_v(with) in dB
  (positive: the measure lowers the vibration), and overall (the levels' energy sums over the bands the
  model resolves: up to the sensor's resolved frequency, soil.mesh.f_max_hz, when the run records one;
  the figure shades the bands above it);
- the change of PPV and KB_Fmax, and each DIN 4150 verdict without and with the measure;
- mitigation.csv (per band), mitigation_summary.csv, mitigation.md (tables; which measure brings each
  verdict to OK) and mitigation.png (IL against band, one line per measure, one panel per receiver).

usage (the tables again from a finished study's bags, e.g. after a change of this module):
  mitigation.py STUDY_DIR [--catalogue FILE]
"""
import csv
import math
import pathlib
import sys

import yaml

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402

import railvib_plots  # noqa: E402
import railvib_verdicts as verdicts  # noqa: E402
import railvib_yaml  # noqa: E402

BASELINE = "baseline"


class CatalogueError(Exception):
    pass


def load_catalogue(path):
    """{name: {"description": str, "set": {dotted key: value}}} of a catalogue file; CatalogueError if malformed."""
    path = pathlib.Path(path)
    try:
        data = railvib_yaml.load(path.read_text())
    except (OSError, yaml.YAMLError) as e:
        raise CatalogueError(f"{path}: {e}")
    if not isinstance(data, dict) or set(data) != {"measures"} or not isinstance(data["measures"], dict):
        raise CatalogueError(f"{path}: a map with one key, measures: {{NAME: {{description, set}}}}")
    out = {}
    for name, m in data["measures"].items():
        where = f"{path}: measures.{name}"
        if not isinstance(name, str) or not name.replace("_", "").isalnum() or name == BASELINE:
            raise CatalogueError(f"{where}: a measure's name is letters, digits and _ (and not '{BASELINE}')")
        if not isinstance(m, dict) or set(m) - {"description", "set"} or "set" not in m:
            raise CatalogueError(f"{where}: a map of description and set")
        keys = m["set"]
        if not isinstance(keys, dict) or not keys:
            raise CatalogueError(f"{where}.set: a non-empty map of dotted configuration keys")
        for key in keys:
            parts = str(key).split(".")
            if len(parts) < 2 or not all(p and p.replace("_", "").isalnum() for p in parts):
                raise CatalogueError(f"{where}.set: '{key}' is not a dotted configuration key (e.g. track.railpad.stiffness_n_m)")
        out[name] = {"description": str(m.get("description", "")), "set": dict(keys)}
    return out


def pick(catalogue, names, path):
    """The named measures in the order given; CatalogueError naming the unknown one and the known ones."""
    chosen = []
    for name in names:
        if name not in catalogue:
            raise CatalogueError(f"unknown measure '{name}' (catalogue {path}: {', '.join(sorted(catalogue)) or 'none'})")
        if name in (c for c, _ in chosen):
            raise CatalogueError(f"measure '{name}' given twice")
        chosen.append((name, catalogue[name]))
    if not chosen:
        raise CatalogueError("no measure given (--measure NAME)")
    return chosen


def override_text(key, value):
    """key=value as railvib_tool's --set takes it (the value as one line of YAML)."""
    text = yaml.safe_dump(value, default_flow_style=True, width=1 << 20).strip()
    if text.endswith("\n..."):
        text = text[:-4].strip()
    return f"{key}={text}"


def energy_level(levels_db):
    """The level of the bands' energy sum (dB)."""
    finite = [v for v in levels_db if math.isfinite(v)]
    return 10.0 * math.log10(sum(10.0 ** (v / 10.0) for v in finite)) if finite else float("nan")


def resolved_limit_hz(metrics):
    """The highest band centre the record resolves (the sensor's resolved_hz; inf when none is recorded)."""
    r = getattr(metrics, "resolved_hz", 0.0)
    return r if r and r > 0 and math.isfinite(r) else math.inf


def insertion_loss(base, with_measure):
    """ISO 14837-1 per band, and overall over the resolved bands, for one sensor's two VibrationMetrics
    (bands must match)."""
    fb, fw = list(base.third_octave_center_hz), list(with_measure.third_octave_center_hz)
    if fb != fw:
        raise ValueError(f"sensor {base.sensor_name}: the runs' one-third octave bands differ ({len(fb)} vs {len(fw)})")
    lb, lw = list(base.third_octave_level_db), list(with_measure.third_octave_level_db)
    if len(lb) != len(fb) or len(lw) != len(fb):
        raise ValueError(f"sensor {base.sensor_name}: band levels and centres differ in count")
    per_band = [b - w for b, w in zip(lb, lw)]
    limit = resolved_limit_hz(base)
    keep = [i for i, f in enumerate(fb) if f <= limit]
    return fb, per_band, energy_level([lb[i] for i in keep]) - energy_level([lw[i] for i in keep])


def summarise(baseline_metrics, measure_results):
    """Rows per (measure, sensor): the band ILs and the summary. measure_results: [(name, description, metrics)]."""
    bands, summary = [], []
    for name, description, metrics in measure_results:
        for sensor in sorted(baseline_metrics):
            b = baseline_metrics[sensor]
            m = metrics.get(sensor)
            if m is None:
                continue
            centres, il, overall = insertion_loss(b, m)
            for f, v in zip(centres, il):
                bands.append({"measure": name, "sensor": sensor, "band_hz": f, "il_db": v})
            summary.append({
                "measure": name, "description": description, "sensor": sensor, "overall_il_db": overall,
                "resolved_hz": resolved_limit_hz(b),
                "ppv_base_mm_s": b.ppv_m_s * 1e3, "ppv_with_mm_s": m.ppv_m_s * 1e3,
                "ppv_change_pct": 100.0 * (m.ppv_m_s / b.ppv_m_s - 1.0) if b.ppv_m_s > 0 else float("nan"),
                "kb_f_max_base": b.kb_f_max, "kb_f_max_with": m.kb_f_max,
                "kind": verdicts.kind_name(b.kind),
                "din4150_2_base": verdicts.verdict_name(b.din4150_2_verdict),
                "din4150_2_with": verdicts.verdict_name(m.din4150_2_verdict),
                "din4150_3_base": verdicts.verdict_name(b.din4150_3_verdict),
                "din4150_3_with": verdicts.verdict_name(m.din4150_3_verdict),
            })
    return bands, summary


SUMMARY_COLUMNS = ["measure", "sensor", "kind", "overall_il_db", "resolved_hz", "ppv_base_mm_s", "ppv_with_mm_s", "ppv_change_pct",
                   "kb_f_max_base", "kb_f_max_with", "din4150_2_base", "din4150_2_with", "din4150_3_base",
                   "din4150_3_with", "description"]


def write_outputs(outdir, bands, summary, wall_s):
    """mitigation.csv, mitigation_summary.csv, mitigation.md, mitigation.png; returns the file names."""
    outdir = pathlib.Path(outdir)
    with open(outdir / "mitigation.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["measure", "sensor", "band_hz", "il_db"], lineterminator="\n")
        w.writeheader()
        w.writerows(bands)
    with open(outdir / "mitigation_summary.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=SUMMARY_COLUMNS, lineterminator="\n", extrasaction="ignore")
        w.writeheader()
        w.writerows(summary)
    fmt = lambda v: f"{v:.3g}" if isinstance(v, float) else str(v)  # noqa: E731
    resolved = sorted({s_["resolved_hz"] for s_ in summary if math.isfinite(s_["resolved_hz"])})
    overall = ("Overall: the bands' energy sums up to the model's resolved frequency ("
               + ", ".join(f"{r:g} Hz" for r in resolved)
               + "; the bands above are not resolved and are shaded in the figure)." if resolved
               else "Overall: the bands' energy sums.")
    lines = ["# railvib mitigation: insertion loss of each measure", "",
             "IL = L_v(without) - L_v(with) per one-third octave band (ISO 14837-1; levels re 1e-9 m/s, the "
             "sensors' core metrics over the whole record); positive: the measure lowers the vibration. "
             + overall, "",
             "| measure | sensor (kind) | overall IL [dB] | PPV [mm/s] without -> with | change | KB_Fmax without -> with "
             "| DIN 4150-2 | DIN 4150-3 |", "|---|---|---|---|---|---|---|---|"]
    for s in summary:
        lines.append(f"| {s['measure']} | {s['sensor']} ({s['kind']}) | {fmt(s['overall_il_db'])} | {fmt(s['ppv_base_mm_s'])} -> "
                     f"{fmt(s['ppv_with_mm_s'])} | {s['ppv_change_pct']:+.1f} % | {fmt(s['kb_f_max_base'])} -> "
                     f"{fmt(s['kb_f_max_with'])} | {s['din4150_2_base']} -> {s['din4150_2_with']} | "
                     f"{s['din4150_3_base']} -> {s['din4150_3_with']} |")
    lines += ["", "## Verdicts brought to OK", ""]
    sensors = sorted({s["sensor"] for s in summary})
    for sensor in sensors:
        for standard in ("din4150_2", "din4150_3"):
            rows = [s for s in summary if s["sensor"] == sensor]
            # Only a verdict that fails without the measures (a free-field sensor has none to bring to OK).
            if not rows or rows[0][standard + "_base"] not in ("WARN", "ERROR"):
                continue
            fixed = [s["measure"] for s in rows if s[standard + "_with"] == "OK"]
            lines.append(f"- {sensor}, {standard.replace('din', 'DIN ').replace('_', '-')} "
                         f"({rows[0][standard + '_base']} without): " + (", ".join(fixed) if fixed else "no measure"))
    lines += ["", "## Descriptions and wall times", ""]
    for name in dict.fromkeys(s["measure"] for s in summary):
        desc = next(s["description"] for s in summary if s["measure"] == name)
        lines.append(f"- {name}: {desc} ({wall_s.get(name, float('nan')):.0f} s)")
    lines.append(f"- {BASELINE}: the scenario without a measure ({wall_s.get(BASELINE, float('nan')):.0f} s)")
    lines += ["", "![insertion loss](mitigation.png)", ""]
    (outdir / "mitigation.md").write_text("\n".join(lines) + "\n")
    # One panel per receiver: IL against band, one line per measure.
    fig, axes = plt.subplots(1, max(1, len(sensors)), figsize=(4.2 * max(1, len(sensors)), 4.0), squeeze=False)
    measures = list(dict.fromkeys(b["measure"] for b in bands))
    # A colour and a line style of its own for each measure (matplotlib's cycle repeats after ten).
    colours = plt.get_cmap("tab20").colors
    styles = [(colours[(2 * i) % 20 + (i // 10) % 2], ("-", "--", ":", "-.")[i // 20 % 4], "os^v"[i // 10 % 4])
              for i in range(len(measures))]
    for ax, sensor in zip(axes[0], sensors):
        for name, (colour, line, marker) in zip(measures, styles):
            pts = [(b["band_hz"], b["il_db"]) for b in bands if b["sensor"] == sensor and b["measure"] == name]
            pts = [(f, v) for f, v in pts if math.isfinite(v)]
            if pts:
                ax.semilogx([p[0] for p in pts], [p[1] for p in pts], marker=marker, ls=line, color=colour, ms=3,
                            label=name)
        ax.axhline(0.0, color="k", lw=0.8)
        limits = [s_["resolved_hz"] for s_ in summary if s_["sensor"] == sensor and math.isfinite(s_["resolved_hz"])]
        top = max((b["band_hz"] for b in bands if b["sensor"] == sensor), default=0.0)
        if limits and top > min(limits):
            ax.axvspan(min(limits) * 2 ** (1 / 6), top * 2 ** (1 / 6), color="0.88", zorder=0,
                       label=f"above f_max {min(limits):g} Hz (not resolved)")
        # The bands' own centres as ticks (every other one when there are many), plain numbers.
        centres = sorted({b["band_hz"] for b in bands if b["sensor"] == sensor})
        ticks = centres[:: max(1, (len(centres) + 9) // 10)]
        ax.set_xticks(ticks)
        ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
        ax.set_title(sensor, fontsize=10)
        ax.set_xlabel("one-third octave band [Hz]")
        ax.grid(alpha=0.3, which="both")
    axes[0][0].set_ylabel("insertion loss [dB]")
    axes[0][0].legend(fontsize=7)
    railvib_plots.fit_title(fig, "railvib mitigation: insertion loss (ISO 14837-1), positive = lower vibration")
    fig.tight_layout()
    fig.savefig(outdir / "mitigation.png", dpi=110)
    plt.close(fig)
    return ["mitigation.md", "mitigation.csv", "mitigation_summary.csv", "mitigation.png"]


def main(argv):
    """The tables and figure again from a finished study's run bags (labels, wall times: study.csv)."""
    import argparse
    import study
    ap = argparse.ArgumentParser(prog="mitigation.py", description="insertion loss from a finished study")
    ap.add_argument("study_dir")
    ap.add_argument("--catalogue", default=str(pathlib.Path(__file__).resolve().parents[1] / "config" /
                                           "mitigation.yaml"))
    a = ap.parse_args(argv[1:])
    outdir = pathlib.Path(a.study_dir)
    try:
        catalogue = load_catalogue(a.catalogue)
        with open(outdir / "study.csv", newline="") as f:
            runs = {}
            for row in csv.DictReader(f):
                runs.setdefault(int(row["run"]), (row["label"], float(row["wall_s"] or "nan")))
    except (CatalogueError, OSError, KeyError, ValueError) as e:
        print(f"railvib mitigation: error: {e}", file=sys.stderr)
        return 2
    results = []
    for index in sorted(runs):
        label, seconds = runs[index]
        bag = outdir / f"run_{index:03d}" / "run.bag"
        if not bag.exists():
            print(f"railvib mitigation: error: {bag} missing", file=sys.stderr)
            return 2
        results.append((label, seconds, study.last_metrics(bag)))
    if not results or results[0][0] != BASELINE:
        print(f"railvib mitigation: error: {outdir}: run 1 is not the baseline", file=sys.stderr)
        return 2
    unknown = [label for label, _, _ in results[1:] if label not in catalogue]
    if unknown:
        print(f"railvib mitigation: error: measures not in {a.catalogue}: {', '.join(unknown)}", file=sys.stderr)
        return 2
    done = [(label, catalogue[label]["description"], m) for label, _, m in results[1:]]
    bands, summary = summarise(results[0][2], done)
    files = write_outputs(outdir, bands, summary, {label: seconds for label, seconds, _ in results})
    print(f"railvib mitigation: {', '.join(str(outdir / f) for f in files)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
