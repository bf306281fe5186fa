#!/usr/bin/env python3
"""railvib study: one scenario run over a list or a grid of overrides, and one table of the results.

usage: ./railvib study [--file STUDY.yaml] [--vary KEY=V1,V2,...]... [--set KEY=VALUE]...
                       [--arg NAME:=VALUE]... [--scenario haren] [--config FILE] [--jobs N] [--outdir DIR]
       ./railvib mitigate --measure NAME [--measure NAME]... [--catalogue FILE] [the options above]

KEY is a launch argument of the scenario (speed, foundation, track, coupling, vehicle, duration,
width, defect_rails, building) or a dotted config key (e.g. unevenness.defect.depth_m), which may
name a list entry by its index (soil.layers[0].young_modulus_pa). --vary keys form a grid (every
combination); --set and --arg hold for every run. A study file says the same in YAML:

    scenario: haren                 # launch file (launch/<scenario>.launch)
    config: config/haren.yaml       # base configuration (default: the launch file's)
    arguments: {duration: 3.0}      # launch arguments of every run
    set: {unevenness.defect.depth_m: 1.0e-3}
    grid: {speed: [2.78, 8.33], foundation: [clm, winkler]}
    runs:                           # and/or explicit runs, each a map of keys (label optional)
      - {label: rigid track, track: rigid}

Each run is a separate `./railvib run` (its own master port, JOBS at a time) into
OUTDIR/run_NNN/ (run.bag, its report, config.yaml with the run's config keys, run.log). The study
writes OUTDIR/study.csv (one row per run and sensor: the varied values, PPV, governing component,
its peak, dominant frequency and DIN 4150-3 guideline, KB_Fmax, both verdicts; values from the
sensors' last /sensor_metrics message, the core's), OUTDIR/study.md (the same, one table) and one
figure per varied key (PPV and KB_Fmax of every sensor against it). Progress and an ETA are printed
as runs finish. Every run's launch arguments and config keys are checked by railvib_tool config-check
(the loaders' own checks) before any run. Exit code: 0 if every run passed, 1 if one failed (the table says which), 2
for a bad study.

With --measure (./railvib mitigate), the runs are the scenario without any measure (the baseline) and
once with each named measure of the catalogue (config/mitigation.yaml, or --catalogue FILE: NAME:
{description, set: {dotted keys}}); besides the study's tables it writes the insertion loss of each
measure (scripts/mitigation.py: mitigation.md, mitigation.csv per band, mitigation_summary.csv,
mitigation.png).
"""
import argparse
import concurrent.futures
import csv
import itertools
import os
import pathlib
import re
import subprocess
import sys
import threading
import time

import numpy as np
import yaml

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import mitigation  # noqa: E402
import railvib_names as names  # noqa: E402
import railvib_plots  # noqa: E402
import railvib_process  # noqa: E402
import railvib_yaml  # noqa: E402
from railvib_paths import find_railvib_tool, OutputDirError, output_dir  # noqa: E402
import railvib_verdicts as verdicts  # noqa: E402

try:
    import rosbag
except ImportError:  # pragma: no cover
    sys.exit("railvib study: python3-rosbag is required (./railvib setup installs it)")

ROOT = pathlib.Path(__file__).resolve().parents[1]
# The launch arguments the nodes map to config keys (src/ros/node_config.cpp) and the launch files'
# own structural ones; anything else with no dot is refused.
LAUNCH_ARGUMENTS = {"speed", "foundation", "duration", "track", "coupling", "vehicle", "width", "defect_rails", "building",
                    "sim_time"}
# The launch files' own arguments (which nodes run, the clock): no config key stands behind them. The
# others the nodes map to config keys (scenario::launchArgumentKeys), which config-check --arg does too.
STRUCTURAL_ARGUMENTS = {"building", "sim_time"}
UNITS = {"speed": "m/s", "duration": "s"}  # launch arguments; config keys carry their unit in the name
COMPONENTS = ("x", "y", "z")


def die(msg):
    print("railvib study: error: " + msg, file=sys.stderr)
    sys.exit(2)


def parse_value(text):
    """A number as a number (also 2e-3, which YAML 1.1 reads as a word), else the value as YAML reads it."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    try:
        return railvib_yaml.load(text)
    except yaml.YAMLError:
        return text


# One step of a config key path: a word, or a word and the index of a list entry under it (layers[0]).
KEY_STEP = re.compile(r"[A-Za-z0-9_]+(\[[0-9]+\])*")


def is_config_key(key):
    """A config key path (a.b.c, soil.layers[0].x), as opposed to a launch argument (a plain word)."""
    return "." in key or "[" in key


def check_key(key):
    if is_config_key(key):
        if not all(KEY_STEP.fullmatch(p) for p in key.split(".")):
            die(f"config key '{key}': expected dotted words like unevenness.defect.depth_m "
                "(a list entry by its index: soil.layers[0].thickness_m)")
        return
    if key not in LAUNCH_ARGUMENTS:
        die(f"'{key}' is neither a launch argument ({', '.join(sorted(LAUNCH_ARGUMENTS))}) nor a dotted config key")


def check_value(key, value):
    if isinstance(value, (list, dict)) or value is None:
        die(f"{key}: one plain value per run, not {value!r}")


def plan(spec):
    """The runs of a study spec: a list of (label, {key: value}) with the fixed keys merged in."""
    fixed = dict(spec.get("arguments") or {})
    fixed.update(spec.get("set") or {})
    grid = spec.get("grid") or {}
    explicit = spec.get("runs") or []
    for key, value in fixed.items():
        check_key(key)
        check_value(key, value)
    for key, values in grid.items():
        check_key(key)
        if not isinstance(values, list) or not values:
            die(f"grid {key}: a non-empty list of values")
        for v in values:
            check_value(key, v)
    runs = []
    if grid:
        keys = list(grid)
        for combination in itertools.product(*(grid[k] for k in keys)):
            varied = dict(zip(keys, combination))
            runs.append((", ".join(f"{k}={v}" for k, v in varied.items()), {**fixed, **varied}))
    for i, run in enumerate(explicit):
        if not isinstance(run, dict):
            die(f"runs[{i}]: a map of keys")
        run = dict(run)
        label = str(run.pop("label", "") or ", ".join(f"{k}={v}" for k, v in run.items()) or f"run {i + 1}")
        for key, value in run.items():
            check_key(key)
            check_value(key, value)
        runs.append((label, {**fixed, **run}))
    if not runs:
        runs.append(("base", dict(fixed)))
    return runs


def measure_runs(spec, measures):
    """The mitigation runs: the baseline (the fixed keys), then each measure's keys over them."""
    fixed = dict(spec.get("arguments") or {})
    fixed.update(spec.get("set") or {})
    for key, value in fixed.items():
        check_key(key)
        check_value(key, value)
    if spec.get("grid") or spec.get("runs"):
        die("--measure runs the baseline and the measures: no --vary, grid or runs beside it")
    runs = [(mitigation.BASELINE, dict(fixed))]
    for name, m in measures:
        for key in m["set"]:
            check_key(key)  # a measure's value may be a list or a map (e.g. soil.inclusions)
        runs.append((name, {**fixed, **m["set"]}))
    return runs


def varied_keys(runs):
    """Keys whose value differs between runs (the study's parameters), in first-seen order."""
    keys = []
    for _, values in runs:
        for k in values:
            if k not in keys:
                keys.append(k)
    return [k for k in keys if len({repr(v.get(k)) for _, v in runs}) > 1]


def nested(dotted):
    """{a.b.c: v} -> {a: {b: {c: v}}} (a run's config keys as a config file's sections)."""
    out = {}
    for key, value in dotted.items():
        node = out
        parts = key.split(".")
        for p in parts[:-1]:
            node = node.setdefault(p, {})
            if not isinstance(node, dict):
                die(f"config key {key}: {p} is set both as a value and as a section")
        node[parts[-1]] = value
    return out


def list_path(key):
    """The dotted path of the list a key's first index is into (soil.layers[0].x -> soil.layers), else None."""
    return key.split("[", 1)[0] if "[" in key else None


def checked_run_lists(base_config, label, values, tool):
    """Checks a run's configuration with the loader before any run (railvib_tool config-check --dump over
    the base with the run's launch arguments, as the nodes map them, and its config keys: every loader's
    checks, the loader's own rule for an index and its refusal of one past the end), and returns the
    lists its indexed keys change (soil.layers[0].young_modulus_pa), each whole as the run has it,
    keyed by the list's dotted path: an included file's list is replaced whole by the including
    file's, so the run's config file holds the list. The lists hold no file names (the one file key,
    unevenness.measured_profile.file, is in no list), whose meaning would change with the file that
    holds them. Without railvib_tool, the run is checked when it starts, and a key into a list is
    refused."""
    config_keys = [k for k in values if is_config_key(k)]
    indexed = [k for k in config_keys if list_path(k)]
    arguments = launch_arguments({k: v for k, v in values.items() if k not in STRUCTURAL_ARGUMENTS})
    if not config_keys and not arguments:
        return {}
    if not tool:
        if indexed:
            die(f"run {label}: a key into a list ({indexed[0]}) needs railvib_tool (./railvib setup builds it)")
        return {}
    command = [tool, "config-check", "--config", str(base_config), "--dump"]
    for argument in arguments:
        command += ["--arg", argument]
    for key in config_keys:
        command += ["--set", mitigation.override_text(key, values[key])]
    r = subprocess.run(command, capture_output=True, text=True)
    if r.returncode != 0:
        die(f"run {label}: {(r.stderr or r.stdout).strip()}")
    merged = railvib_yaml.load(r.stdout)
    lists = {}
    for key in indexed:
        path = list_path(key)
        node = merged
        for step in path.split("."):
            if not isinstance(node, dict) or step not in node:
                die(f"run {label}: {key}: no list {path} in the merged configuration")
            node = node[step]
        if not isinstance(node, list):
            die(f"run {label}: {key}: {path} is not a list")
        lists[path] = node
    return lists


def write_run_config(run_dir, base_config, values, lists):
    """config.yaml of a run: the base config included, the run's config keys over it (the lists its
    indexed keys change, whole: checked_run_lists)."""
    config = {"include": [str(base_config)]}
    plain = {k: v for k, v in values.items() if is_config_key(k) and not list_path(k)}
    for path in lists:  # a key inside one of the lists is in the list already
        plain = {k: v for k, v in plain.items() if k != path and not k.startswith(path + ".")}
    config.update(nested({**plain, **lists}))
    path = run_dir / "config.yaml"
    path.write_text("# railvib study run: the base configuration with this run's keys over it\n"
                    + yaml.safe_dump(config, sort_keys=False))
    return path


def launch_arguments(values):
    out = []
    for k, v in values.items():
        if is_config_key(k):
            continue
        if isinstance(v, bool):
            v = "true" if v else "false"
        out.append(f"{k}:={v}")
    return out


def last_metrics(bag_path):
    """The last VibrationMetrics of each sensor in a run's bag (they cover the whole record)."""
    last = {}
    with rosbag.Bag(str(bag_path)) as bag:
        for _, m, _ in bag.read_messages(topics=[names.SENSOR_METRICS]):
            last[m.sensor_name] = m
    return last


class Progress:
    """One line per finished run with the ETA from the mean duration of the runs so far."""

    def __init__(self, total, jobs):
        self.total, self.jobs, self.done, self.start = total, jobs, 0, time.monotonic()
        self.lock = threading.Lock()
        self.seconds = []

    def finished(self, label, seconds, ok):
        with self.lock:
            self.done += 1
            self.seconds.append(seconds)
            left = self.total - self.done
            eta = np.mean(self.seconds) * left / self.jobs if left else 0.0
            print(f"railvib study: [{self.done}/{self.total}] {label}: {'done' if ok else 'FAILED'} in {seconds:.0f} s; "
                  f"elapsed {time.monotonic() - self.start:.0f} s, ETA {eta:.0f} s", flush=True)


def run_one(index, label, values, lists, options, base_config, progress):
    run_dir = options.outdir / f"run_{index + 1:03d}"
    run_dir.mkdir(parents=True, exist_ok=True)
    bag = run_dir / "run.bag"
    for stale in run_dir.glob("run*.bag"):  # a study re-run replaces its own runs' bags
        stale.unlink()
    config = write_run_config(run_dir, base_config, values, lists)
    command = options.runner + [options.scenario] + launch_arguments(values) + [f"config:={config}", f"bag:={bag}"]
    env = dict(os.environ)
    env["RAILVIB_SKIP_SETUP"] = "1"
    env["RAILVIB_ROS_PORT"] = str(railvib_process.free_port())  # each run a master of its own
    env["RAILVIB_COMMAND_LINE"] = f"./railvib study (run {index + 1}: {label}): " + " ".join(command[1:])
    start = time.monotonic()
    with open(run_dir / "run.log", "w") as log:
        code = subprocess.run(command, stdout=log, stderr=subprocess.STDOUT, env=env, cwd=ROOT).returncode
    seconds = time.monotonic() - start
    result = {"index": index + 1, "label": label, "values": values, "dir": run_dir, "code": code, "seconds": seconds,
              "metrics": {}, "error": ""}
    if bag.exists():
        try:
            result["metrics"] = last_metrics(bag)
        except Exception as e:  # a truncated bag: the run failed, say why
            result["error"] = f"bag unreadable: {e}"
    if code != 0 and not result["error"]:
        result["error"] = f"./railvib run exited {code} (see {run_dir / 'run.log'})"
    progress.finished(label, seconds, code == 0)
    return result


def rows_of(results, keys):
    rows = []
    for r in results:
        base = {"run": r["index"], "label": r["label"], **{k: r["values"].get(k, "") for k in keys},
                "status": "ok" if r["code"] == 0 else "failed", "wall_s": round(r["seconds"], 1)}
        if not r["metrics"]:
            rows.append({**base, "sensor": "", "error": r["error"]})
            continue
        for sensor, m in sorted(r["metrics"].items()):
            rows.append({**base, "sensor": sensor,
                         "ppv_mm_s": m.ppv_m_s * 1e3,
                         "governing_component": COMPONENTS[m.governing_component],
                         "governing_ppv_mm_s": m.governing_ppv_m_s * 1e3,
                         "dominant_frequency_hz": m.dominant_frequency_hz,
                         "din4150_3_limit_mm_s": m.din4150_3_limit_m_s * 1e3,
                         "kb_f_max": m.kb_f_max,
                         "kind": verdicts.kind_name(m.kind),
                         "din4150_2": verdicts.verdict_name(m.din4150_2_verdict),
                         "din4150_3": verdicts.verdict_name(m.din4150_3_verdict),
                         "error": r["error"]})
    return rows


COLUMNS = ["kind", "ppv_mm_s", "governing_component", "governing_ppv_mm_s", "dominant_frequency_hz", "din4150_3_limit_mm_s",
           "kb_f_max", "din4150_2", "din4150_3"]


def write_tables(outdir, rows, keys):
    header = ["run", "label"] + keys + ["status", "wall_s", "sensor"] + COLUMNS + ["error"]
    with open(outdir / "study.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=header, lineterminator="\n", extrasaction="ignore")
        w.writeheader()
        for row in rows:
            w.writerow({k: row.get(k, "") for k in header})

    def cell(v):
        return f"{v:.4g}" if isinstance(v, float) else str(v)

    lines = ["# railvib study", "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(cell(row.get(k, "")) for k in header) + " |" for row in rows]
    lines += ["", "PPV: vector peak; the governing component is DIN 4150-3's (its peak against the guideline at "
              "its dominant frequency); KB_Fmax and the DIN 4150-2 verdict on it (WARN: between A_u and A_o, "
              "the rating KB_FTr decides). Values as each run's virtual sensors recorded them."]
    (outdir / "study.md").write_text("\n".join(lines) + "\n")


def plot_against(outdir, rows, keys):
    """Per varied key: PPV and KB_Fmax of every sensor against it (other keys' combinations as separate lines)."""
    figures = []
    good = [r for r in rows if r.get("sensor")]
    for key in keys:
        others = [k for k in keys if k != key]
        values = []
        for r in good:
            if r[key] not in values:
                values.append(r[key])
        numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)
        position = {v: (v if numeric else i) for i, v in enumerate(values)}
        fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
        series = {}
        for r in good:
            series.setdefault((r["sensor"],) + tuple(r[k] for k in others), []).append((position[r[key]], r))
        for (sensor, *rest), points in sorted(series.items(), key=lambda kv: str(kv[0])):
            points.sort(key=lambda p: p[0])
            label = sensor + ("" if not rest else " (" + ", ".join(f"{k}={v}" for k, v in zip(others, rest)) + ")")
            x = [p for p, _ in points]
            axes[0].plot(x, [r["ppv_mm_s"] for _, r in points], "o-", label=label)
            axes[1].plot(x, [r["kb_f_max"] for _, r in points], "o-", label=label)
        # Vibration levels span decades (the 2 m sensor against the house): log axes, as the standards'
        # own figures have them; a numeric key spanning more than a decade on a log axis too.
        positive_x = numeric and all(v > 0 for v in values)
        log_x = positive_x and max(values) >= 10.0 * min(values)
        for ax, ylabel, field in zip(axes, ("PPV [mm/s]", "KB_Fmax [-]"), ("ppv_mm_s", "kb_f_max")):
            ax.set_xlabel(key + (f" [{UNITS[key]}]" if key in UNITS else ""))
            ax.set_ylabel(ylabel)
            if all(r[field] > 0 for r in good):
                ax.set_yscale("log")
            if log_x:
                ax.set_xscale("log")
            ax.grid(alpha=0.3, which="both")
            if not numeric:
                ax.set_xticks(range(len(values)))
                ax.set_xticklabels([str(v) for v in values])
        axes[0].legend(fontsize=7)
        railvib_plots.fit_title(fig, f"railvib study: sensors against {key}")
        fig.tight_layout()
        name = "study_" + "".join(c if c.isalnum() else "_" for c in key) + ".png"
        fig.savefig(outdir / name, dpi=110)
        plt.close(fig)
        figures.append(name)
    return figures


def load_spec(options):
    spec = {}
    if options.file:
        try:
            spec = railvib_yaml.load(pathlib.Path(options.file).read_text()) or {}
        except (OSError, yaml.YAMLError) as e:
            die(f"{options.file}: {e}")
        if not isinstance(spec, dict):
            die(f"{options.file}: a map (scenario, config, arguments, set, grid, runs)")
        unknown = set(spec) - {"scenario", "config", "arguments", "set", "grid", "runs"}
        if unknown:
            die(f"{options.file}: unknown key(s) {', '.join(sorted(unknown))} "
                "(scenario, config, arguments, set, grid, runs)")
    spec.setdefault("arguments", {})
    spec.setdefault("set", {})
    spec.setdefault("grid", {})
    for text in options.arg:
        name, sep, value = text.partition(":=")
        if not sep or not name:
            die(f"--arg {text}: NAME:=VALUE")
        spec["arguments"][name] = parse_value(value)
    for text in options.set:
        key, sep, value = text.partition("=")
        if not sep or not key:
            die(f"--set {text}: KEY=VALUE")
        spec["set"][key] = parse_value(value)
    for text in options.vary:
        key, sep, values = text.partition("=")
        if not sep or not key or not values:
            die(f"--vary {text}: KEY=V1,V2,...")
        spec["grid"][key] = [parse_value(v) for v in values.split(",")]
    return spec


def main(argv):
    parser = argparse.ArgumentParser(prog="./railvib study", description=__doc__.split("\n")[0])
    parser.add_argument("--file", help="study file (YAML)")
    parser.add_argument("--vary", action="append", default=[], help="KEY=V1,V2,... (a grid axis)")
    parser.add_argument("--set", action="append", default=[], help="KEY=VALUE for every run")
    parser.add_argument("--arg", action="append", default=[], help="NAME:=VALUE launch argument for every run")
    parser.add_argument("--scenario", help="launch file name (default haren)")
    parser.add_argument("--config", help="base configuration file (default: the scenario's)")
    parser.add_argument("--jobs", type=int, default=1, help="runs at a time (each uses the cores it can)")
    parser.add_argument("--outdir", help="default bags/study_<time>")
    parser.add_argument("--runner", default=str(ROOT / "railvib") + " run",
                        help=argparse.SUPPRESS)  # tests: a command that stands in for ./railvib run
    parser.add_argument("--dry-run", action="store_true", help="print the runs and stop")
    parser.add_argument("--measure", action="append", default=[],
                        help="a measure of the catalogue (repeatable): the baseline and each measure are run")
    parser.add_argument("--catalogue", default=str(ROOT / "config" / "mitigation.yaml"),
                        help="the measures' catalogue (default config/mitigation.yaml)")
    options = parser.parse_args(argv[1:])
    spec = load_spec(options)
    options.scenario = options.scenario or spec.get("scenario") or "haren"
    if not (ROOT / "launch" / f"{options.scenario}.launch").exists():
        die(f"no scenario '{options.scenario}' (launch/{options.scenario}.launch)")
    base = pathlib.Path(options.config or spec.get("config") or ROOT / "config" / f"{options.scenario}.yaml")
    if not base.is_absolute():
        base = (pathlib.Path.cwd() / base) if (pathlib.Path.cwd() / base).exists() else ROOT / base
    if not base.exists():
        die(f"base configuration {base} does not exist")
    if options.jobs < 1:
        die("--jobs must be >= 1")
    if options.measure:
        try:
            measures = mitigation.pick(mitigation.load_catalogue(options.catalogue), options.measure,
                                       options.catalogue)
        except mitigation.CatalogueError as e:
            die(str(e))
        runs = measure_runs(spec, measures)
        keys = []
    else:
        measures = []
        runs = plan(spec)
        keys = varied_keys(runs)
    # Before any run: every run through the loader's checks (and a key into a list resolved).
    tool = find_railvib_tool()
    if not tool:
        print("railvib study: railvib_tool not found: each run's configuration is checked when it starts")
    run_list_values = [checked_run_lists(base, label, values, tool) for label, values in runs]
    print(f"railvib study: {len(runs)} run(s) of {options.scenario}, {options.jobs} at a time, base {base}")
    for i, (label, values) in enumerate(runs):
        print(f"  run {i + 1:3d}: {label}  [{' '.join(launch_arguments(values))}"
              f"{' ' if any(is_config_key(k) for k in values) else ''}"
              f"{' '.join(f'{k}={v}' for k, v in values.items() if is_config_key(k))}]")
    if options.dry_run:
        return 0
    options.outdir = pathlib.Path(options.outdir or ROOT / "bags" / time.strftime("study_%Y%m%d_%H%M%S"))
    try:
        output_dir(options.outdir)
    except OutputDirError as e:
        die(str(e))
    options.runner = options.runner.split()
    (options.outdir / "study.yaml").write_text(yaml.safe_dump({**spec, "scenario": options.scenario,
                                                              "config": str(base)}, sort_keys=False))
    progress = Progress(len(runs), options.jobs)
    with concurrent.futures.ThreadPoolExecutor(max_workers=options.jobs) as pool:
        futures = [pool.submit(run_one, i, label, values, lists, options, base, progress)
                   for i, ((label, values), lists) in enumerate(zip(runs, run_list_values))]
        results = [f.result() for f in futures]
    rows = rows_of(results, keys)
    write_tables(options.outdir, rows, keys)
    figures = plot_against(options.outdir, rows, keys) if keys else []
    failed = [r for r in results if r["code"] != 0]
    if measures and results[0]["metrics"]:
        described = {name: m["description"] for name, m in measures}
        done = [(r["label"], described[r["label"]], r["metrics"]) for r in results[1:] if r["metrics"]]
        try:
            bands, summary = mitigation.summarise(results[0]["metrics"], done)
            figures += mitigation.write_outputs(options.outdir, bands, summary,
                                                {r["label"]: r["seconds"] for r in results})
        except ValueError as e:
            print(f"railvib study: no insertion loss: {e}")
            failed = failed or results[:1]
    print(f"railvib study: {options.outdir / 'study.md'}, study.csv"
          + (f", {', '.join(figures)}" if figures else "")
          + (f"; {len(failed)} run(s) failed: " + ", ".join(r["label"] for r in failed) if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
