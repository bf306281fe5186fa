#!/usr/bin/env python3
"""railvib robustness cases: what an adversarial user feeds railvib, and what railvib does with it.

usage: robustness.py [--groups config,csv,nodes,bags,launch] [--table FILE] [--junit FILE] [--json FILE] [--check]
       robustness.py --from-json RESULTS.json... --table FILE

Each case feeds one bad input to the program a user would run, and classifies the outcome:

  refused clearly  non-zero exit, and the message names what is wrong (the key, file and line,
                   stream and field, or bag topic: the case's expected fragment) with no traceback;
  crash            a signal, a sanitizer report, a Python traceback, an uncaught C++ exception;
  silent           exit 0: the bad input was accepted;
  unclear          refused, but the message does not say what is wrong.

Groups: config (railvib_tool config-check on bad scenarios and overrides), csv (the files the
tools read: loads, records, footprint velocities), nodes (each stream node alone, fed mutated
messages: test/ros/node_fuzz.py), bags (./railvib report on bad bags), launch (runs that must fail:
an existing bag, a full disk, a refused or injected argument, a killed node or master).

--table writes the Markdown table of docs/robustness.md (counts per group, then every case);
--check exits 1 unless every case was refused clearly (the suite runs it: CTest robustness_cases).
Run it in the workspace environment: ./railvib exec python3 scripts/robustness.py --table docs/robustness.md
"""
import argparse
import json
import os
import pathlib
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

import yaml

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import railvib_names as names  # noqa: E402
import railvib_process  # noqa: E402
import railvib_yaml  # noqa: E402
from railvib_paths import find_railvib_tool  # noqa: E402

CRASH_MARKERS = ("AddressSanitizer", "UndefinedBehaviorSanitizer", "runtime error:", "Segmentation fault",
                 "Traceback (most recent call last)", "terminate called", "core dumped", "Aborted")
CONFIG = ROOT / "config"
CI = str(CONFIG / "haren_ci.yaml")
HAREN = str(CONFIG / "haren.yaml")
WORK = pathlib.Path(tempfile.mkdtemp(prefix="railvib_robustness_"))
TOOL = find_railvib_tool()


def classify(code, output, fragment, expected_codes):
    marker = next((m for m in CRASH_MARKERS if m in output), None)
    if marker or (code is not None and code < 0):
        return "crash", marker or f"signal {-code}"
    if code == 0:
        return "silent", "exit 0"
    if code in expected_codes and fragment in output:
        line = next((l for l in output.splitlines() if fragment in l), fragment)
        return "refused", line.strip()[:240]
    return "unclear", f"exit {code}, '{fragment}' not in: {output.strip()[-300:]}"


def run(cmd, timeout=600, env=None, cwd=None):
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd=cwd,
                             start_new_session=True)
        return out.returncode, out.stdout + out.stderr
    except subprocess.TimeoutExpired as e:
        return None, f"timed out after {timeout} s: {(e.stdout or b'')[-500:]}"


def write(name, text, binary=False):
    path = WORK / name
    path.parent.mkdir(parents=True, exist_ok=True)
    if binary:
        path.write_bytes(text)
    else:
        path.write_text(text)
    return path


# ----------------------------------------------------------------- config
def merged_ci():
    code, out = run([TOOL, "config-check", "--config", CI, "--dump"])
    assert code == 0, out
    return railvib_yaml.load(out)


def config_cases():
    """(title, config-check args, fragment)."""
    tree = merged_ci()

    def mutated(name, fn):
        t = json.loads(json.dumps(tree))
        fn(t)
        return ["--config", str(write(f"config/{name}.yaml", yaml.safe_dump(t, sort_keys=False)))]

    def ci(*sets):
        return ["--config", CI] + [a for s in sets for a in ("--set", s)]

    cases = [
        ("negative speed", ci("simulation.speed_m_s=-5"), "simulation.speed_m_s = -5"),
        ("speed NaN", ci("simulation.speed_m_s=.nan"), "simulation.speed_m_s"),
        ("duration infinite", ci("simulation.duration_s=.inf"), "simulation.duration_s"),
        ("time step 0", ci("simulation.time_step_s=0"), "simulation.time_step_s = 0"),
        ("time step as text", ci("simulation.time_step_s=abc"), "simulation.time_step_s = abc"),
        ("speed with a unit", ci("simulation.speed_m_s=30km/h"), "simulation.speed_m_s = 30km/h"),
        ("railpad stiffness 1e300", ci("track.railpad.stiffness_n_m=1e300"), "track.railpad.stiffness_n_m"),
        ("negative ballast stiffness", ci("track.ballast.stiffness_n_m=-3.2e7"), "track.ballast.stiffness_n_m"),
        ("fractional element count", ci("track.rail.elements_per_bay=2.5"), "track.rail.elements_per_bay = 2.5"),
        ("integer beyond long", ci("building.storeys=99999999999999999999"), "building.storeys"),
        ("sleeper spacing 0", ci("track.sleeper.spacing_m=0"), "track.sleeper.spacing_m = 0"),
        ("track extent reversed", ci("track.extent.mode=fixed", "track.extent.x_min_m=-50", "track.extent.x_max_m=-60"),
         "track.extent.x_max_m = -60"),
        ("automatic track extent set by hand", ci("track.extent.x_max_m=60"), "track.extent.x_max_m"),
        ("track margin negative", ci("track.extent.margin_m=-3"), "track.extent.margin_m = -3"),
        ("unknown foundation model", ci("track.foundation.model=elastic"), "track.foundation.model = elastic"),
        ("active CLM chain", ci("track.foundation.clm.coupling_damping_n_s_m=-1e6"), "coupling_damping_n_s_m"),
        ("bad value in the foundation not chosen", ci("track.foundation.winkler.damping_n_s_m=-1"),
         "track.foundation.winkler.damping_n_s_m = -1"),
        ("load rate 0", ci("track.output.load_sample_rate_hz=0"), "track.output.load_sample_rate_hz = 0"),
        ("carbody without mass", ci("vehicles.t2000.bodies.front_carbody.mass_kg=0"),
         "vehicles.t2000.bodies.front_carbody.mass_kg = 0"),
        ("wheel on no body", ci("vehicles.t2000.wheels=[{name: axle0, body: ghost, type: motor, radius_m: 0.34}]"),
         "vehicles.t2000.wheels[0].body = ghost"),
        ("wheel of no known type", ci("vehicles.t2000.wheels=[{name: axle0, body: axle0_tread, type: steam, radius_m: 0.34}]"),
         "vehicles.t2000.wheels[0].type = steam"),
        ("wheel radius 3 m", ci("vehicles.t2000.wheels=[{name: axle0, body: axle0_tread, type: motor, radius_m: 3.0}, "
                                 "{name: axle1, body: axle1_trailer_wheel, type: trailer, radius_m: 0.34}, "
                                 "{name: axle2, body: axle2_tread, type: motor, radius_m: 0.34}, "
                                 "{name: axle3, body: axle3_tread, type: motor, radius_m: 0.34}, "
                                 "{name: axle4, body: axle4_trailer_wheel, type: trailer, radius_m: 0.34}, "
                                 "{name: axle5, body: axle5_tread, type: motor, radius_m: 0.34}]"),
         "vehicles.t2000.wheels[0].radius_m = 3"),
        ("Hertz constant 1e300", ci("vehicles.t2000.contact.hertz_constant_n_m1_5=1e300"), "hertz_constant_n_m1_5"),
        ("defect 0.5 m high", ci("unevenness.defect.height_m=0.5"), "unevenness.defect.height_m = 0.5"),
        ("defect off the track", ci("unevenness.defect.position_m=200"), "unevenness.defect.position_m = 200"),
        ("incompressible soil", ci("soil.half_space.poisson_ratio=0.5"), "soil.half_space.poisson_ratio = 0.5"),
        ("Rayleigh beta 2 s", ci("soil.rayleigh_beta_s=2"), "soil.rayleigh_beta_s = 2"),
        ("f_max 0", ci("soil.mesh.f_max_hz=0"), "soil.mesh.f_max_hz = 0"),
        ("soil box reversed", ci("soil.mesh.x_max_m=-20"), "soil.mesh.x_max_m = -20"),
        ("1000 threads", ci("soil.mesh.threads=1000"), "soil.mesh.threads = 1000"),
        ("half precision", ci("soil.mesh.precision=half"), "soil.mesh.precision = half"),
        ("receiver rate not a multiple of the snapshot rate", ci("soil.output.receiver_rate_hz=333"),
         "soil.output.snapshot_rate_hz"),
        ("boundary method unknown", ci("soil.boundary.method=sponge"), "soil.boundary.method = sponge"),
        # (the scenario files hold a pml section; the override removes it)
        ("PML chosen without its section", ci("soil.boundary.method=pml", "soil.boundary.pml=~"),
         "soil.boundary.pml = (missing)"),
        ("outside_mesh policy unknown", ci("soil.loads.outside_mesh=ignore"), "soil.loads.outside_mesh = ignore"),
        ("wall shear modulus inconsistent", ci("building.walls.shear_modulus_pa=1e9"), "building.walls.shear_modulus_pa"),
        ("no storey", ci("building.storeys=0"), "building.storeys = 0"),
        ("floor thicker than a storey", ci("building.floors.thickness_m=3"), "building.floors.thickness_m = 3"),
        ("house element size 10 m", ci("building.mesh.element_size_m=10"), "building.mesh.element_size_m = 10"),
        ("damping band reversed", ci("building.damping.f2_hz=5"), "building.damping.f2_hz = 5"),
        ("unknown coupling", ci("building.coupling=three_way"), "building.coupling = three_way"),
        ("rail gauge 5 m", ci("site.rail_gauge_m=5"), "site.rail_gauge_m = 5"),
        ("house on the track", ci("site.building.front_wall_distance_from_rail_m=-1"),
         "front_wall_distance_from_rail_m = -1"),
        ("ground sensor outside the soil box",
         mutated("sensor_far", lambda t: t["virtual_sensors"]["sensors"][1].update(y_m=500.0)), "ground_8m"),
        ("sensor rate 5 Hz", ci("virtual_sensors.sample_rate_hz=5"), "virtual_sensors.sample_rate_hz = 5"),
        ("metrics faster than samples", ci("virtual_sensors.metrics_rate_hz=5000"), "virtual_sensors.metrics_rate_hz"),
        ("unknown DIN 4150-2 period", ci("virtual_sensors.din4150_2_period=evening"), "din4150_2_period = evening"),
        ("negative noise", ci("virtual_sensors.noise_rms_m_s2=-1"), "virtual_sensors.noise_rms_m_s2 = -1"),
        ("sensor source unknown",
         mutated("source", lambda t: t["virtual_sensors"]["sensors"].__setitem__(
             0, {"name": "ground_2m", "source": "attic", "point": "ground_2m"})),
         "virtual_sensors.sensors[0].source = attic"),
        ("sensor with a position and a source",
         mutated("placed_source", lambda t: t["virtual_sensors"]["sensors"][0].update(source="soil")),
         "virtual_sensors.sensors[0].source = soil: a sensor with a position"),
        ("free-field sensor above the ground",
         mutated("placed_z", lambda t: t["virtual_sensors"]["sensors"][0].update(z_m=1.0)),
         "virtual_sensors.sensors[0].z_m"),
        ("house sensor outside the house",
         mutated("placed_out", lambda t: t["virtual_sensors"]["sensors"][3].update(x_m=12.0)),
         "virtual_sensors.sensors[3].x_m = 12"),
        ("a point placed twice",
         mutated("placed_twice", lambda t: t["virtual_sensors"]["sensors"][1].update(point="ground_2m")),
         "point 'ground_2m' is defined twice"),
        ("sensor at no output point",
         mutated("point", lambda t: t["virtual_sensors"]["sensors"].__setitem__(
             1, {"name": "ground_8m", "source": "soil", "point": "ground_9m"})),
         "virtual_sensors.sensors[1].point = ground_9m"),
        ("two sensors of one name",
         mutated("dupname", lambda t: t["virtual_sensors"]["sensors"][1].update(name="ground_2m", point="ground_8m")),
         "duplicate sensor name"),
        ("sensor rate above the soil's", ci("virtual_sensors.sample_rate_hz=2000"), "virtual_sensors.sample_rate_hz"),
        ("velocity bound 0", ci("limits.velocity_m_s=0"), "limits.velocity_m_s = 0"),
        ("contact force bound NaN", ci("limits.contact_force_n=.nan"), "limits.contact_force_n"),
        # unknown keys
        ("misspelt key", ci("soil.mesh.f_max_hzz=40"), "did you mean soil.mesh.f_max_hz?"),
        ("misspelt section", ci("simulaton.speed_m_s=5"), "did you mean simulation?"),
        ("misspelt key next to the real one", ci("track.railpad.stifness_n_m=1"),
         "did you mean track.railpad.stiffness_n_m?"),
        ("misspelt key in a list entry",
         mutated("pointt", lambda t: t["virtual_sensors"]["sensors"][0].update(pointt="x")),
         "did you mean virtual_sensors.sensors[0].point?"),
        ("misspelt required key",
         mutated("required", lambda t: t["simulation"].update(speed_ms=t["simulation"].pop("speed_m_s"))),
         "is 'simulation.speed_ms' a misspelling"),
        ("unknown section", mutated("meshh", lambda t: t["soil"].update(meshh={"a": 1})), "soil.meshh"),
        ("misspelt optional key", ci("building.footprint.nxx=3"), "did you mean building.footprint.nx?"),
        # memory, cross-checks, files
        ("mesh beyond the machine, cap raised", ["--config", HAREN, "--set", "soil.mesh.max_memory_gb=9999", "--set",
                                                "soil.mesh.f_max_hz=800"], "of memory of this machine"),
        ("mesh beyond max_memory_gb", ci("soil.mesh.max_memory_gb=0.0001"), "soil.mesh.max_memory_gb = 0.0001"),
        ("mesh beyond any machine", ci("soil.mesh.f_max_hz=9000", "soil.mesh.elements_per_wavelength=100"),
         "any machine could hold"),
        ("load rate above the step rate", ci("track.output.load_sample_rate_hz=200000"), "above the rate"),
        ("load rate below Nyquist of the soil", ci("track.output.load_sample_rate_hz=30"), "below twice"),
        ("measured profile missing", ci("unevenness.measured_profile.enabled=true",
                                        "unevenness.measured_profile.file=/nonexistent/profile.csv"), "no such file"),
    ]
    for name, text, fragment in [
        ("NaN in the measured profile", "x_m,z_m\n-10,0\n0,nan\n10,0\n", "is not a finite number"),
        ("measured profile not increasing", "x_m,z_m\n-10,0\n-20,0\n", "must be greater"),
        ("measured profile 5 m high", "x_m,z_m\n-10,0\n0,5\n10,0\n", "limits.unevenness_m"),
        ("measured profile cut short", "x_m,z_m\n-10,0\n0,1.5e", "no end of line"),
    ]:
        path = write(f"profiles/{name.replace(' ', '_')}.csv", text)
        cases.append((name, ci("unevenness.measured_profile.enabled=true",
                               f"unevenness.measured_profile.file={path}"), fragment))
    bomb = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"{c}: &{c} [{', '.join(['*' + p] * 9)}]\n" for p, c in zip("abcdefghi", "bcdefghij"))
    wide = "a: &a [" + ", ".join(str(i) for i in range(1000)) + "]\nb: [" + ", ".join(["*a"] * 200) + "]\n"
    ci_text = pathlib.Path(CI).read_text()
    files = [
        ("alias bomb", write("yaml/bomb.yaml", bomb), "aliases nested"),
        ("alias expansion", write("yaml/wide.yaml", wide), "once its aliases are expanded"),
        ("a value that contains itself", write("yaml/cycle.yaml", "track: &t\n  sleeper: *t\n"),
         "would contain itself"),
        ("10 MB config", write("yaml/big.yaml", "a:\n" + "  # padding\n" * 1000000), "bytes, more than"),
        ("a directory as config", WORK, "is a directory, not a config file"),
        ("missing config", WORK / "none.yaml", "file not found"),
        ("a device as config", pathlib.Path("/dev/null"), "not a regular file"),
        ("binary garbage", write("yaml/garbage.yaml", bytes(range(256)) * 4, binary=True), "config error in"),
        ("empty config", write("yaml/empty.yaml", ""), "required key is missing"),
        ("a list at the top", write("yaml/list.yaml", "- a\n- b\n"), "top level must be a map"),
        ("include cycle", write("yaml/cycle_a.yaml", "include: [cycle_b.yaml]\n"), "include cycle"),
        ("include of a missing file", write("yaml/inc_missing.yaml", "include: [nothere.yaml]\n"), "file not found"),
        ("include entry not a file name", write("yaml/inc_map.yaml", "include: [{a: 1}]\n"), "include entry"),
        ("nested 100 deep", write("yaml/deep.yaml", "a: " + "[" * 100 + "]" * 100 + "\n"), "nested deeper than"),
        ("two YAML documents", write("yaml/two.yaml", ci_text + "\n---\na: 1\n"), "more than one YAML document"),
        ("a list as a key", write("yaml/listkey.yaml", "? [a, b]\n: 1\n"), "a key must be a plain name"),
        ("a section twice", write("dup/sections.yaml", "include: [" + CI + "]\nsimulation: {duration_s: 0.2}\n"
                                  "simulation: {duration_s: 0.3}\n"), "duplicate key 'simulation'"),
        ("a key twice", write("dup/key.yaml", "include: [" + CI + "]\nsimulation:\n  duration_s: 0.2\n"
                              "  duration_s: 0.3\n"), "duplicate key 'simulation.duration_s'"),
        ("a key twice in an included file", write("dup/top.yaml", "include: [inc.yaml]\n"), "duplicate key"),
    ]
    write("yaml/cycle_b.yaml", "include: [cycle_a.yaml]\n")
    write("dup/inc.yaml", ci_text.replace("simulation:\n", "simulation:\n  duration_s: 0.1\n", 1).replace(
        "include:\n  - haren.yaml", "include:\n  - " + HAREN))
    for title, path, fragment in files:
        cases.append((title, ["--config", str(path)], fragment))
    cases += [
        ("override without a value", ci("simulation.speed_m_s"), "must look like key.path=value"),
        ("override not YAML", ci("simulation.speed_m_s=[1,"), "not valid YAML"),
        ("a number for a section", ci("soil=3"), "soil = 3"),
        ("a map for a number", ci("simulation.speed_m_s={a: 1}"), "simulation.speed_m_s"),
        ("not a boolean", ci("virtual_sensors.include_gravity=maybe"), "virtual_sensors.include_gravity = maybe"),
        ("10 000-character value", ci("virtual_sensors.din4150_2_period=" + "x" * 10000), "din4150_2_period"),
        ("a list entry that does not exist", ci("soil.layers[99].thickness_m=2"), "soil.layers has"),
        ("a list index that is not a position", ci("soil.layers[-1].thickness_m=2"), "is not a list position"),
        ("an index on a key that is no list", ci("simulation[0].speed_m_s=8"), "simulation is not a list"),
        ("a bad value in one list entry", ci("soil.layers[1].thickness_m=abc"), "soil.layers[1].thickness_m = abc"),
        ("an unknown snapshot component", ci("soil.output.snapshot_components=sideways"), "allowed: all, vertical"),
        ("an unknown soil box mode", ci("soil.mesh.extent.mode=huge"), "allowed: fixed, auto"),
    ]
    return cases


def config_group():
    results = []
    for title, args, fragment in config_cases():
        code, out = run([TOOL, "config-check"] + args, timeout=300)
        outcome, detail = classify(code, out, fragment, {3})
        if outcome == "refused" and "config error" not in out:
            outcome, detail = "unclear", "no 'config error' line: " + detail
        results.append({"group": "configuration", "case": title, "outcome": outcome, "detail": detail})
    return results


# ----------------------------------------------------------------- CSV
def loads_csv(rows=20, sleepers=139, edit=None, newline_at_end=True):
    lines = ["t_s," + ",".join(f"sleeper_{j}" for j in range(sleepers))]
    for i in range(rows):
        lines.append(",".join([repr(i * 5e-4)] + [repr(10000.0 + j) for j in range(sleepers)]))
    if edit:
        edit(lines)
    return "\n".join(lines) + ("\n" if newline_at_end else "")


def record_csv(rows=200, edit=None, newline_at_end=True):
    lines = ["t_s,vx,vy,vz"] + [f"{i * 1e-3!r},1e-4,2e-4,{3e-4 * ((i % 7) - 3)!r}" for i in range(rows)]
    if edit:
        edit(lines)
    return "\n".join(lines) + ("\n" if newline_at_end else "")


def csv_cases():
    """(title, command, fragment)."""
    def soil(name, text, extra=()):
        path = write(f"csv/{name}.csv", text)
        return [TOOL, "soil", "--config", CI, "--loads", str(path), "--out", str(WORK / "soil_out" / name),
                "--duration", "0.004"] + list(extra)

    def set_cell(row, col, value):
        def edit(lines):
            cells = lines[row].split(",")
            cells[col] = value
            lines[row] = ",".join(cells)
        return edit

    cases = [
        ("loads: NaN force", soil("nan", loads_csv(edit=set_cell(5, 10, "nan"))), "csv/nan.csv:6"),
        ("loads: infinite force", soil("inf", loads_csv(edit=set_cell(5, 10, "inf"))), "is not a finite number"),
        ("loads: 1e300 N", soil("huge", loads_csv(edit=set_cell(5, 10, "1e300"))), "limits.soil_load_n"),
        ("loads: 40000kN", soil("unit", loads_csv(edit=set_cell(3, 2, "40000kN"))), "'40000kN' is not a number"),
        ("loads: last number cut short", soil("cut", loads_csv(edit=set_cell(20, 139, "1.2e"), newline_at_end=False)),
         "no end of line"),
        ("loads: half a number", soil("half", loads_csv(edit=set_cell(20, 139, "1.2e"))), "'1.2e' is not a number"),
        ("loads: time goes back", soil("back", loads_csv(edit=lambda l: l.insert(10, l[9]))), "does not increase"),
        ("loads: one step shorter", soil("uneven", loads_csv(edit=set_cell(12, 0, repr(11.5 * 5e-4)))),
         "uniformly spaced"),
        ("loads: first sample not at 0", soil("late", loads_csv(edit=lambda l: l.pop(1))), "must be at t = 0"),
        ("loads: a row too long", soil("long", loads_csv(edit=lambda l: l.__setitem__(4, l[4] + ",1"))),
         "expected 140 values, got 141"),
        ("loads: no t_s column", soil("notime", loads_csv(edit=lambda l: l.__setitem__(0, l[0].replace("t_s", "time")))),
         "expected columns t_s"),
        ("loads: empty file", soil("empty", ""), "empty CSV file"),
        ("loads: a directory", [TOOL, "soil", "--config", CI, "--loads", str(WORK), "--out", str(WORK / "so")],
         "is a directory"),
        ("loads: 10 sleeper positions for 139 columns",
         soil("sl10", loads_csv(), ["--sleepers", str(write("csv/sleepers10.csv", "sleeper,x_m\n" + "".join(
             f"{i},{i * 0.72}\n" for i in range(10))))]), "139 sleeper columns but 10 sleeper positions"),
        ("loads: sleeper positions not increasing",
         soil("slback", loads_csv(), ["--sleepers", str(write("csv/sleepers_back.csv", "sleeper,x_m\n" + "".join(
             f"{i},{(i if i != 5 else 1) * 0.72}\n" for i in range(139))))]), "must increase"),
    ]

    def metrics(name, text, column="vx,vy,vz"):
        path = write(f"csv/{name}.csv", text)
        return [TOOL, "metrics", "--csv", str(path), "--column", column]

    cases += [
        ("record: NaN velocity", metrics("m_nan", record_csv(edit=set_cell(50, 3, "nan"))), "m_nan.csv:51"),
        ("record: 1e300 m/s", metrics("m_huge", record_csv(edit=set_cell(50, 3, "1e300"))), "limits.velocity_m_s"),
        ("record: time not uniform", metrics("m_uneven", record_csv(edit=set_cell(100, 0, "0.0995"))),
         "uniformly spaced"),
        ("record: time goes back", metrics("m_back", record_csv(edit=lambda l: l.insert(30, l[29]))),
         "does not increase"),
        ("record: unit suffix", metrics("m_unit", record_csv(edit=set_cell(3, 1, "1e-4m/s"))), "is not a number"),
        ("record: column missing", metrics("m_col", record_csv(), "vx,vy,vw"), "no column 'vw'"),
        ("record: cut short", metrics("m_cut", record_csv(newline_at_end=False)), "no end of line"),
    ]
    code, out = run([TOOL, "building-footprint", "--config", CI])
    footprint = [p["name"] for p in json.loads(out)["points"]] if code == 0 else []
    header = "time_s," + ",".join(f"{n}{c}" for n in footprint for c in ("_vx", "_vy", "_vz"))

    def footprint_csv(name, edit=None):
        lines = [header] + [",".join([repr(i * 1e-3)] + ["1e-5"] * (3 * len(footprint))) for i in range(50)]
        if edit:
            edit(lines)
        path = write(f"csv/{name}.csv", "\n".join(lines) + "\n")
        return [TOOL, "building-response", "--config", CI, "--footprint", str(path), "--out",
                str(WORK / f"{name}_out.csv")]

    cases += [
        ("footprint: NaN velocity", footprint_csv("f_nan", set_cell(10, 5, "nan")), "f_nan.csv:11"),
        ("footprint: time not uniform", footprint_csv("f_uneven", set_cell(20, 0, "0.0195")), "uniformly spaced"),
        ("footprint: 1e300 m/s", footprint_csv("f_huge", set_cell(10, 5, "1e300")), "limits.velocity_m_s"),
    ]
    return cases


def csv_group():
    results = []
    for title, cmd, fragment in csv_cases():
        code, out = run(cmd, timeout=600)
        outcome, detail = classify(code, out, fragment, {1, 2})
        results.append({"group": "files read by the tools", "case": title, "outcome": outcome, "detail": detail})
    return results


# ----------------------------------------------------------------- bags
def bag_cases():
    import rosbag
    import rospy
    from std_msgs.msg import String
    from tf2_msgs.msg import TFMessage
    import railvib.msg as rm

    def block(cls, first, count, points, eos, period, arrays, count_field):
        m = cls()
        m.first_sample_index, m.end_of_stream, m.sample_period_s, m.sample_count = first, eos, period, count
        setattr(m, count_field, points)
        for field, per in arrays:
            setattr(m, field, [1.0 + i for i in range(count * points * per)])
        return m

    def cf(first, count, eos):
        return block(rm.ContactForces, first, count, 2, eos, 1e-5,
                     [("position_m", 1), ("force_n", 1), ("unevenness_m", 1)], "wheel_count")

    def sl(first, count, eos):
        m = block(rm.SoilLoads, first, count, 3, eos, 5e-4, [("force_n", 1)], "sleeper_count")
        m.seats_per_sleeper = 1  # the half track: one force per sleeper
        return m

    def bag(name, messages, status="closed: all streams complete",
            expected=(names.CONTACT_FORCES, names.SOIL_LOADS)):
        path = WORK / "bags" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        with rosbag.Bag(str(path), "w") as b:
            for topic, m in messages:
                b.write(topic, m, rospy.Time(0, 1))
            if status is not None:
                b.write(names.RECORDING_STATUS, String(data=json.dumps(
                    {"status": status, "expected_streams": list(expected)})), rospy.Time(0, 1))
        return path

    good = [(names.CONTACT_FORCES, cf(0, 5, True)), (names.SOIL_LOADS, sl(0, 4, True))]
    whole = bag("whole.bag", good)
    data = whole.read_bytes()
    nan = sl(0, 4, True)
    nan.force_n[2] = float("nan")
    malformed = sl(0, 4, True)
    malformed.sleeper_count = 1000
    return [
        ("a foreign bag", bag("foreign.bag", [("/chatter", String(data="hi"))], status=None), "not a railvib bag"),
        ("railvib names, other types", bag("types.bag", [(names.CONTACT_FORCES, String(data="x"))], status=None),
         "has type std_msgs/String"),
        ("only /tf_static", bag("tf.bag", [("/tf_static", TFMessage())], status=None), "not a railvib bag"),
        ("a truncated bag", write("bags/half.bag", data[: len(data) // 2], binary=True), "cannot read"),
        ("an empty file", write("bags/empty.bag", b"", binary=True), "cannot read"),
        ("a text file", write("bags/text.bag", "not a bag\n"), "cannot read"),
        ("a directory", WORK / "bags", "cannot read"),
        ("a stream that sent no block", bag("nosoil.bag", good[:1]), names.SOIL_LOADS + ": no block recorded"),
        ("a stream without its end", bag("noend.bag", [(names.CONTACT_FORCES, cf(0, 5, False)), good[1]]),
         names.CONTACT_FORCES + ": stops at sample 5"),
        ("a malformed block", bag("malformed.bag", [good[0], (names.SOIL_LOADS, malformed)]), "values, not sample_count"),
        ("NaN in a stream", bag("nan.bag", [good[0], (names.SOIL_LOADS, nan)]), "not finite"),
        ("the recorder stopped on a full disk", bag("full.bag", good, status="failed: disk full: 0 MB free"),
         "disk full"),
    ]


def bags_group():
    results = []
    for title, path, fragment in bag_cases():
        code, out = run([sys.executable, str(ROOT / "scripts" / "report.py"), str(path), str(WORK / "report_out")])
        outcome, detail = classify(code, out, fragment, {1, 2})
        results.append({"group": "bags given to the report", "case": title, "outcome": outcome, "detail": detail})
    return results


# ----------------------------------------------------------------- launches
PORT = [0]  # the master's port of the case being run: a free one each time


def launcher(args, env=None, kill=None, kill_after_s=0.0, prefix=(), timeout=600):
    """launch_scenario.py on a master of its own; optionally kill a node or the master mid-run."""
    PORT[0] = railvib_process.free_port()
    env = dict(env or os.environ, ROS_MASTER_URI=f"http://localhost:{PORT[0]}")
    cmd = list(prefix) + [sys.executable, str(ROOT / "scripts" / "launch_scenario.py"), "-p", str(PORT[0])] + args
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                            start_new_session=True)
    if kill:
        deadline = time.time() + 120
        while time.time() < deadline and proc.poll() is None:
            listed = subprocess.run(["rosnode", "list"], env=env, capture_output=True, text=True, timeout=30)
            if kill == "/master" and listed.returncode == 0 and listed.stdout.strip():
                break
            if kill in listed.stdout.split():
                break
            time.sleep(0.2)
        time.sleep(kill_after_s)
        if kill == "/master":
            import rosgraph
            pid = rosgraph.Master("/robustness", master_uri=env["ROS_MASTER_URI"]).getPid()
            os.kill(pid, signal.SIGKILL)
        else:
            subprocess.run(["rosnode", "kill", kill], env=env, capture_output=True, timeout=60)
    try:
        out, _ = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        out, _ = railvib_process.stop(proc, grace_s=60.0)
        return None, out
    return proc.returncode, out


def track(*extra, duration="0.3"):
    return ["railvib", "track.launch", "speed:=2.0", f"duration:={duration}"] + list(extra)


def launch_group():
    results = []

    def add(title, code, out, fragment, extra_ok=True, extra_detail=""):
        outcome, detail = classify(code, out, fragment, {1})
        if outcome == "refused" and not extra_ok:
            outcome, detail = "unclear", extra_detail
        results.append({"group": "runs that must fail", "case": title, "outcome": outcome, "detail": detail})

    existing = write("launch/existing.bag", "an earlier run's results\n")
    code, out = launcher(track(f"bag:={existing}"))
    add("the bag exists", code, out, "refusing to overwrite",
        existing.read_text() == "an earlier run's results\n", "the existing bag was changed")

    code, out = launcher(track("speed:=-5", f"bag:={WORK / 'launch' / 'neg.bag'}"))
    add("a refused launch argument", code, out, "simulation.speed_m_s = -5")

    code, out = launcher(track('speed:=5", "soil.mesh.max_memory_gb=9999', f"bag:={WORK / 'launch' / 'inj.bag'}"))
    add("an argument that injects another key", code, out, "must be one plain value")

    typo = write("launch/typo.yaml", f"include: [{HAREN}]\nsimulation:\n  sped_m_s: 3\n")
    code, out = launcher(["railvib", "track.launch", f"config:={typo}", f"bag:={WORK / 'launch' / 'typo.bag'}"])
    add("a misspelt key in the scenario", code, out, "did you mean simulation.speed_m_s?")

    code, out = launcher(track(f"bag:={WORK / 'launch' / 'killed.bag'}", duration="3.0"), kill="/track",
                         kill_after_s=0.5)
    add("a required node killed", code, out, "REQUIRED process [track")

    code, out = launcher(track(f"bag:={WORK / 'launch' / 'master.bag'}", duration="3.0"), kill="/master",
                         kill_after_s=0.5)
    add("the master killed", code, out, "railvib: launch failed")

    # A full disk: the bag on a 3 MB tmpfs of a private mount namespace (root: unshare -m; else a user
    # namespace too). The bag is copied out before the namespace (and its tmpfs) goes.
    full_dir, out_dir = WORK / "tmpfs", WORK / "launch"
    full_dir.mkdir(parents=True, exist_ok=True)
    unshare = ["unshare", "-m"] if os.geteuid() == 0 else ["unshare", "-r", "-m"]
    PORT[0] = railvib_process.free_port()
    inner = (f"mount -t tmpfs -o size=3m tmpfs {full_dir} && "
             f"{sys.executable} {ROOT / 'scripts' / 'launch_scenario.py'} -p {PORT[0]} railvib track.launch "
             f"speed:=2.0 duration:=0.3 bag:={full_dir / 'full.bag'}; rc=$?; "
             f"cp {full_dir / 'full.bag'} {out_dir / 'full.bag'}; exit $rc")
    env = dict(os.environ, ROS_MASTER_URI=f"http://localhost:{PORT[0]}")
    code, out = run(unshare + ["sh", "-c", inner], env=env)
    readable = False
    if (out_dir / "full.bag").exists():
        import bag_check
        r = bag_check.check_bag(out_dir / "full.bag")
        readable = r.refused is None and r.code == 1 and bool(r.incomplete)
        out += "\n" + "; ".join(r.findings)
    add("a full disk", code, out, "disk full", readable, "the bag left is not readable with its streams incomplete")
    return results


# ----------------------------------------------------------------- nodes
def node_rows(fuzz_results):
    """The cases of test/ros/node_fuzz.py (its run() or --json) as rows of the table."""
    results = []
    for r in fuzz_results:
        outcome = r["outcome"]
        if outcome == "finished":
            continue  # control cases: a valid stream runs through, not an adversarial case
        results.append({"group": "stream messages, each node alone", "case": r["group"][5:] + ": " + r["case"],
                        "outcome": outcome, "detail": r.get("detail", "")})
    return results


def nodes_group():
    sys.path.insert(0, str(ROOT / "test" / "ros"))
    import node_fuzz
    return node_rows(node_fuzz.run(progress=False))


GROUPS = {"config": config_group, "csv": csv_group, "nodes": nodes_group, "bags": bags_group,
          "launch": launch_group}


def table(results):
    groups = []
    for r in results:
        if r["group"] not in groups:
            groups.append(r["group"])
    lines = ["| inputs | cases tried | refused clearly | crashes | silent | unclear |", "|---|---|---|---|---|---|"]
    total = [0, 0, 0, 0, 0]
    for g in groups + ["**total**"]:
        rs = results if g == "**total**" else [r for r in results if r["group"] == g]
        row = [len(rs)] + [sum(r["outcome"] == o for r in rs) for o in ("refused", "crash", "silent", "unclear")]
        if g != "**total**":
            total = [a + b for a, b in zip(total, row)]
        lines.append(f"| {g} | " + " | ".join(str(x) for x in row) + " |")
    lines += ["", "Every case, with the first line of what railvib said:", ""]
    for g in groups:
        lines += [f"### {g}", "", "| case | outcome | message |", "|---|---|---|"]
        for r in results:
            if r["group"] == g:
                # Without terminal colours and ROS's "[FATAL] [stamp]: " prefix: what was said.
                msg = re.sub(r"\x1b\[[0-9;]*m", "", r["detail"])
                msg = re.sub(r"^\[ ?(FATAL|ERROR|WARN|INFO) ?\] \[[0-9.]+\]: ", "", msg)
                msg = msg.replace("|", "\\|").replace("\n", " ")
                lines.append(f"| {r['case']} | {r['outcome']} | {msg} |")
        lines.append("")
    return "\n".join(lines)


def main(argv):
    railvib_process.interrupts_by_default()
    parser = argparse.ArgumentParser(description="railvib robustness cases")
    parser.add_argument("--groups", default="config,csv,nodes,bags,launch")
    parser.add_argument("--table")
    parser.add_argument("--junit")
    parser.add_argument("--json")
    parser.add_argument("--check", action="store_true")
    parser.add_argument("--from-json", nargs="+", metavar="FILE",
                        help="no run: the table (--table) of results saved by an earlier run (--json of this "
                             "script, or of test/ros/node_fuzz.py), e.g. those of ./railvib test")
    options = parser.parse_args(argv[1:])
    results = []
    if options.from_json:
        for f in options.from_json:
            saved = json.loads(pathlib.Path(f).read_text())
            results += node_rows(saved) if saved and saved[0].get("group", "").startswith("node ") else saved
        options.groups = ""
    elif not TOOL:
        sys.exit("robustness: railvib_tool not found (run in the workspace environment)")
    for g in filter(None, options.groups.split(",")):
        start = time.time()
        got = GROUPS[g]()
        results += got
        bad = [r for r in got if r["outcome"] != "refused"]
        print(f"robustness: {g}: {len(got)} cases, {len(bad)} not refused clearly ({time.time() - start:.0f} s)",
              flush=True)
        for r in bad:
            print(f"  {r['outcome']}: {r['case']}: {r['detail']}", flush=True)
    if options.table:
        doc = pathlib.Path(options.table)
        text = doc.read_text() if doc.exists() else ""
        start, end = "<!-- robustness table: begin -->", "<!-- robustness table: end -->"
        body = start + "\n" + table(results) + "\n" + end
        if start in text and end in text:
            text = text[: text.index(start)] + body + text[text.index(end) + len(end):]
        else:
            text = text + "\n" + body + "\n"
        doc.write_text(text)
    if options.json:
        pathlib.Path(options.json).write_text(json.dumps(results, indent=1))
    if options.junit:
        suite = ET.Element("testsuite", name="robustness_cases", tests=str(len(results)))
        for r in results:
            case = ET.SubElement(suite, "testcase", classname="Robustness." + r["group"].replace(" ", "_"),
                                 name=r["case"])
            if r["outcome"] != "refused":
                ET.SubElement(case, "failure", message=r["outcome"]).text = r["detail"]
        pathlib.Path(options.junit).parent.mkdir(parents=True, exist_ok=True)
        ET.ElementTree(suite).write(options.junit, encoding="utf-8", xml_declaration=True)
    shutil.rmtree(WORK, ignore_errors=True)
    bad = [r for r in results if r["outcome"] != "refused"]
    print(f"robustness: {len(results)} cases, {len(results) - len(bad)} refused clearly, "
          f"{sum(r['outcome'] == 'crash' for r in results)} crashes, "
          f"{sum(r['outcome'] == 'silent' for r in results)} silent, "
          f"{sum(r['outcome'] == 'unclear' for r in results)} unclear")
    return 1 if options.check and (bad or not results) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
