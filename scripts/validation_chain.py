#!/usr/bin/env python3
"""railvib validation, chain part: the paper's claims that need the whole chain (ground spectra at
2 m and 8 m, Winkler vs CLM, house vs free field, first floor vs ground floor, KB_F), from the bags
of `./railvib run` (docs/validation.md).

usage: ./railvib exec python3 scripts/validation_chain.py FREE_FIELD_BAG [--winkler BAG] [--two-way BAG]
                                        [--config FILE] [--out DIR] [--set key=value ...]

FREE_FIELD_BAG and the --winkler bag: runs with building.coupling one_way, whose soil does not see the
house (the free field the paper validated against Haren: `./railvib run haren coupling:=one_way`);
--two-way: the default run, where the house acts on the soil (the house's claims are judged on it).
Each bag's recorded scenario must say so: a bag of the other coupling is refused.

Exports the vertical velocity of every virtual sensor (/sensor_samples) and of the free-field
point at the house's response point (/surface_velocities, `bldg_response_point`) to
OUT/<bag>_sensors.csv (t_s, <name>_vz_m_s), then runs
`railvib_tool validate --no-models --chain ... [--chain-winkler ...] [--chain-two-way ...]`, which
judges the claims
(the verdict logic lives in the core, src/validation/chain_claims.cpp) and exits 4 when a claim
that agreed no longer agrees. Give the --config/--set of the run so the house and the axle times
are those of the bag.
"""
import argparse
import pathlib
import subprocess
import sys

import numpy as np

import railvib_names as names  # noqa: E402
import report  # noqa: E402  (the scenario record: one place)
from railvib_paths import find_railvib_tool  # noqa: E402

try:
    import rosbag
except ImportError:  # pragma: no cover
    sys.exit("validation_chain: python3-rosbag is required (./railvib setup installs it)")


def blocks(bag, topic):
    out = [m for _, m, _ in bag.read_messages(topics=[topic])]
    out.sort(key=lambda m: m.first_sample_index)
    expected = 0
    for b in out:
        if b.first_sample_index != expected:
            sys.exit(f"validation_chain: {topic}: samples {expected}..{b.first_sample_index - 1} missing")
        expected += b.sample_count
    return out


def export(bag_path, out_dir, coupling):
    with rosbag.Bag(str(bag_path)) as bag:
        recorded, why_not = report.recorded_coupling(bag)
        if recorded is None:
            print(f"validation_chain: {bag_path}: building.coupling not known ({why_not}); taken as {coupling}",
                  file=sys.stderr)
        elif recorded != coupling:
            sys.exit(f"validation_chain: {bag_path} ran with building.coupling {recorded}, this input needs "
                     f"{coupling} (the free-field runs: coupling:=one_way; --two-way: the default run)")
        ss = blocks(bag, names.SENSOR_SAMPLES)
        if not ss:
            sys.exit(f"validation_chain: {bag_path} has no {names.SENSOR_SAMPLES}")
        sensor_names = list(ss[0].sensor_names)
        v = np.concatenate([np.array(b.velocity_m_s).reshape(-1, len(sensor_names), 3) for b in ss])
        dt = ss[0].sample_period_s
        columns = {f"{n}_vz_m_s": v[:, i, 2] for i, n in enumerate(sensor_names)}
        receivers = None
        for _, m, _ in bag.read_messages(topics=[names.SURFACE_POINTS]):
            receivers = list(m.names)
            break
        sv = blocks(bag, names.SURFACE_VELOCITIES)
        free = names.BUILDING_RESPONSE_FREE_FIELD_POINT
        if receivers and free in receivers and sv and abs(sv[0].sample_period_s - dt) < 1e-12:
            r = np.concatenate([np.array(b.velocity_m_s).reshape(-1, len(receivers), 3) for b in sv])
            n = min(len(r), len(v))
            columns = {k: c[:n] for k, c in columns.items()}
            columns[f"{free}_vz_m_s"] = r[:n, receivers.index(free), 2]
    n = min(len(c) for c in columns.values())
    path = out_dir / (pathlib.Path(bag_path).stem + "_sensors.csv")
    header = "t_s," + ",".join(columns)
    data = np.column_stack([np.arange(n) * dt] + [c[:n] for c in columns.values()])
    np.savetxt(path, data, delimiter=",", header=header, comments="", fmt="%.10g")
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("bag", help="bag of the free-field CLM run (./railvib run haren coupling:=one_way)")
    ap.add_argument("--winkler", help="bag of the same run with foundation:=winkler (coupling:=one_way)")
    ap.add_argument("--two-way", help="bag of the default run, coupling two_way (the house acts on the soil)")
    ap.add_argument("--config", help="scenario of the runs (default: config/haren.yaml)")
    ap.add_argument("--set", action="append", default=[], help="the run's overrides, key=value")
    ap.add_argument("--out", default=None, help="directory for the exported CSVs (default: next to the bag)")
    ap.add_argument("--markdown", help="write the chain table as Markdown")
    a = ap.parse_args()
    out_dir = pathlib.Path(a.out) if a.out else pathlib.Path(a.bag).parent
    out_dir.mkdir(parents=True, exist_ok=True)
    cmd = [find_railvib_tool() or sys.exit("validation_chain: railvib_tool not found (./railvib setup)"),
           "validate", "--no-models", "--chain", str(export(a.bag, out_dir, "one_way"))]
    if a.winkler:
        cmd += ["--chain-winkler", str(export(a.winkler, out_dir, "one_way"))]
    if a.two_way:
        cmd += ["--chain-two-way", str(export(a.two_way, out_dir, "two_way"))]
    if a.config:
        cmd += ["--config", a.config]
    for s in a.set:
        cmd += ["--set", s]
    if a.markdown:
        cmd += ["--markdown", a.markdown]
    sys.exit(subprocess.run(cmd).returncode)


if __name__ == "__main__":
    main()
