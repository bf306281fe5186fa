#!/usr/bin/env python3
"""Every railvib_tool subcommand, once, on a small case, with a property of its result.

usage: tool_commands.py [--tool RAILVIB_TOOL] [JUNIT_XML]

Each case runs one command (exit 0, a JSON summary on stdout) and asserts something true of what
it computed (an equilibrium, a standard's value, a rigid-body motion, a count), so a command that
runs but computes nonsense fails too. The set of commands is checked against `railvib_tool --help`:
a new command without a case here fails the test.
"""
import argparse
import csv
import json
import math
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

import yaml

ROOT = pathlib.Path(__file__).resolve().parents[2]
CI = str(ROOT / "config" / "haren_ci.yaml")
WORK = pathlib.Path(tempfile.mkdtemp(prefix="railvib_tool_commands_"))


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


class Cases:
    def __init__(self, tool):
        self.tool = tool

    def run(self, *args, timeout=900):
        out = subprocess.run([self.tool] + [str(a) for a in args], capture_output=True, text=True, timeout=timeout)
        check(out.returncode == 0, f"exit {out.returncode}: {out.stderr[-2000:]}")
        return json.loads(out.stdout)

    # ------------------------------------------------------------------ config
    def config_check(self):
        s = self.run("config-check", "--config", CI)
        check(s["valid"] and len(s["virtual_sensors"]) == 4, s)
        # The Haren catalogue's trench passes; a void under the house (front wall at y = 4.72 m) is refused
        # with its key, whether or not a footprint point falls in it.
        trench = "soil.inclusions=[{name: t, kind: void, x_m: [-14.8, 14.8], y_m: [%s], depth_m: [0, 2]}]"
        s = self.run("config-check", "--set", trench % "3.1, 3.9")
        check(s["valid"], s)
        out = subprocess.run([self.tool, "config-check", "--set", trench % "6.1, 6.9"], capture_output=True, text=True)
        check(out.returncode != 0 and "soil.inclusions[0].y_m" in out.stderr and "through the house" in out.stderr,
              out.stderr)
        # The catalogue's resilient wheels pass; a tread heavier than the 160 kg trailer wheel is refused with its key.
        rw = ["--set", "vehicles.t2000.resilient_wheels.enabled=true", "--set", "vehicles.t2000.resilient_wheels.wheels=rigid",
              "--set", "vehicles.t2000.resilient_wheels.tread_mass_kg=80.0",
              "--set", "vehicles.t2000.resilient_wheels.stiffness_n_m=145.0e6",
              "--set", "vehicles.t2000.resilient_wheels.damping_n_s_m=3.0e3"]
        s = self.run("config-check", *rw)
        check(s["valid"], s)
        out = subprocess.run([self.tool, "config-check"] + rw + ["--set", "vehicles.t2000.resilient_wheels.tread_mass_kg=170"],
                             capture_output=True, text=True)
        check(out.returncode != 0 and "resilient_wheels.tread_mass_kg" in out.stderr and "(0, 160) kg" in out.stderr,
              out.stderr)
        # Launch arguments as the nodes map them (speed:= -> simulation.speed_m_s), before the --set overrides.
        dump = subprocess.run([self.tool, "config-check", "--config", CI, "--arg", "speed:=5", "--arg",
                               "foundation:=winkler", "--arg", "duration:=", "--set", "simulation.duration_s=0.25",
                               "--dump"], capture_output=True, text=True)
        check(dump.returncode == 0, dump.stderr)
        merged = yaml.safe_load(dump.stdout)
        check((merged["simulation"]["speed_m_s"], merged["track"]["foundation"]["model"],
               merged["simulation"]["duration_s"]) == (5, "winkler", 0.25), merged["simulation"])
        for arg, message in (("speed:=-1", "simulation.speed_m_s = -1"), ("sped:=5", "not one the nodes know"),
                             ("speed", "expected NAME:=VALUE"), ("speed:=5, soil.x=1", "one plain value")):
            out = subprocess.run([self.tool, "config-check", "--config", CI, "--arg", arg], capture_output=True,
                                 text=True)
            check(out.returncode == 3 and message in out.stderr, f"--arg {arg}: exit {out.returncode}: {out.stderr}")

    # ------------------------------------------------------------------ track
    def receptance(self):
        path = WORK / "receptance.csv"
        s = self.run("receptance", "--config", CI, "--fmin", 10, "--fmax", 300, "--df", 2, "--csv", path)
        check(s["static_receptance_m_n"] > 0 and s["peaks"], s)
        check(len(rows(path)) == s["frequencies"], "one CSV row per frequency")
        # Full width: both rails in phase are the half track; one rail alone rolls the sleeper, so its
        # rail/ballast resonance moves (static: the same, the seats carry their own rail).
        both = self.run("receptance", "--config", CI, "--fmin", 10, "--fmax", 300, "--df", 2, "--csv", path,
                        "--set", "track.width=full", "--load", "both")
        left = self.run("receptance", "--config", CI, "--fmin", 10, "--fmax", 300, "--df", 2, "--csv", path,
                        "--set", "track.width=full", "--load", "left")
        check(abs(both["static_receptance_m_n"] / s["static_receptance_m_n"] - 1) < 1e-9, (both, s))
        check(len(both["peaks"]) == len(s["peaks"]) and
              all(abs(a["frequency_hz"] - b["frequency_hz"]) < 1e-6 for a, b in zip(both["peaks"], s["peaks"])),
              (both, s))
        check(abs(left["static_receptance_m_n"] / s["static_receptance_m_n"] - 1) < 1e-9, (left, s))
        check(left["width"] == "full" and left["load"] == "left", left)
        out = subprocess.run([self.tool, "receptance", "--config", CI, "--csv", path, "--load", "anti"],
                             capture_output=True, text=True)
        check(out.returncode != 0 and "track.width=full" in out.stderr, out.stderr)
        # The ballast on the FE soil (the CI scenario's coarse 25 Hz mesh, a short impulse run): the ground's
        # compliance in series makes the track softer than on a rigid base at low frequency.
        fe_path = WORK / "receptance_fe_soil.csv"
        fe = self.run("receptance", "--config", CI, "--foundation", "fe_soil", "--soil-duration", 0.4,
                      "--soil-pulse", 0.03, "--fmin", 2, "--fmax", 25, "--df", 1, "--csv", fe_path)
        rigid = self.run("receptance", "--config", CI, "--foundation", "rigid", "--fmin", 2, "--fmax", 25, "--df", 1,
                         "--csv", path)
        fe_rows = rows(fe_path)
        check(fe["foundation"] == "fe_soil" and fe["soil_run"]["footprints_each_side"] >= 2 and
              len(fe_rows) == fe["frequencies"], fe)
        check(float(fe_rows[0]["abs"]) > 1.2 * rigid["static_receptance_m_n"], (fe_rows[0], rigid))  # measured 1.48
        for bad, why in ((["--foundation", "fe_soil", "--fmax", 40], "f_max"),
                         (["--foundation", "fe_soil", "--vary", "kf"], "kf"),
                         (["--soil-duration", 1], "fe_soil")):
            out = subprocess.run([self.tool, "receptance", "--config", CI, "--csv", path] + [str(a) for a in bad],
                                 capture_output=True, text=True)
            check(out.returncode != 0 and why in out.stderr, (bad, out.stderr))

    def insertion_loss(self):
        # An under-sleeper pad on the rigid base: the discrete track against the continuous beam on the same
        # layered support (receptance, force into the ground) and the insertion loss's zero crossing.
        path = WORK / "insertion_loss.csv"
        s = self.run("insertion-loss", "--config", CI, "--measure", "usp", "--foundation", "rigid", "--fmin", 2,
                     "--fmax", 300, "--df", 1, "--csv", path)
        check(len(rows(path)) == s["frequencies"], "one CSV row per frequency")
        errors = s["closed_form_errors_up_to_band"]  # 150 Hz: within 2 % (up to f_pp / 2: a few %, docs/track.md)
        check(errors["up_to_hz"] == 150 and
              all(e["max_relative_error"] < 0.02 for k, e in errors.items() if k != "up_to_hz"), errors)
        check(s["min_insertion_loss_db"] < -1 and s["insertion_loss_at_fmax_db"] > 3, s)
        closed = [f for f in s["closed_form_insertion_loss_crossings_hz"] if f > s["f_at_min_insertion_loss_hz"]]
        model = [f for f in s["insertion_loss_crossings_hz"] if f > s["f_at_min_insertion_loss_hz"]]
        check(closed and model and abs(model[0] / closed[0] - 1) < 0.03, s)
        # the CLM has no closed form; a layer's bad value is refused with its key
        clm = self.run("insertion-loss", "--config", CI, "--measure", "ubm", "--fmax", 200, "--df", 2)
        check("closed_form" in clm and clm["min_insertion_loss_db"] < 0, clm)
        out = subprocess.run([self.tool, "insertion-loss", "--config", CI, "--set",
                              "track.under_ballast_mat.bedding_modulus_n_mm3=0"], capture_output=True, text=True)
        check(out.returncode != 0 and "track.under_ballast_mat.bedding_modulus_n_mm3" in out.stderr, out.stderr)

    def moving_load(self):
        path = WORK / "moving_load.csv"
        s = self.run("moving-load", "--config", CI, "--dt", 1e-4, "--rate", 1000, "--duration", 0.7, "--speed", 5,
                     "--csv", path)
        # Quasi-static moving loads: the sleepers carry what the wheels apply (both rails).
        check(s["max_rel_error_sum_soil_loads_vs_applied_after_0_5_s"] < 0.01, s)
        check(s["rows"] == len(rows(path)), "rows")

    def track_bench(self):
        s = self.run("track-bench", "--config", CI, "--length", 40, "--steps", 200, "--repeats", 1)
        check(all(x["us_per_step_moving_loads_median"] > 0 for x in s["solvers"]), s)

    # ------------------------------------------------------------------ vehicle
    def vehicle_modes(self):
        s = self.run("vehicle-modes", "--config", CI)
        f = [m["f0_hz"] for m in s["modes"]]
        check(f and all(x > 0 for x in f) and f == sorted(f), f"modes: {f}")
        # Full width (both rails, roll): the half vehicle's modes are its symmetric ones, and it rolls.
        full = self.run("vehicle-modes", "--config", CI, "--set", "track.width=full")
        check(full["width"] == "full" and "width" not in s, full.keys())
        sym = [m["f0_hz"] for m in full["modes"] if m["antisymmetric_energy_share"] < 0.5]
        check(len(sym) == len(f) and all(abs(a / b - 1) < 1e-9 for a, b in zip(sorted(sym), f)), (sym, f))
        check(any(m["name"] == "car-body roll" for m in full["modes"]), [m["name"] for m in full["modes"]])

    def wheel_impedance(self):
        s = self.run("wheel-impedance", "--config", CI, "--points", 20, "--csv", WORK / "impedance.csv")
        check(s["min_abs_z_n_s_m"] > 0 and 1 <= s["f_at_min_abs_z_hz"] <= 200, s)
        # Full width, both wheels of the axle in phase: the half vehicle's impedance per wheel.
        full = self.run("wheel-impedance", "--config", CI, "--points", 20, "--set", "track.width=full",
                        "--rail", "right", "--load", "both")
        check(full["rail"] == "right" and abs(full["min_abs_z_n_s_m"] / s["min_abs_z_n_s_m"] - 1) < 1e-9, full)
        # Resilient trailer wheels: wheel 1's impedance against the closed form of its chain with the bogie
        # blocked (within 1 % above 250 Hz, the ring's resonance within 0.1 %: docs/vehicle.md "Resilient
        # wheels"); a rigid wheel has no such chain and is refused.
        rw = ["--set", "vehicles.t2000.resilient_wheels.enabled=true"]
        c = self.run("wheel-impedance", "--config", CI, "--wheel", 1, "--f-min", 250, "--f-max", 2000, "--points", 50,
                     "--closed-form", "blocked", *rw)["closed_form"]
        check(c["tread"] == "axle1_trailer_wheel_tread" and c["max_rel_dev"] < 0.01 and
              abs(c["ring_resonance_rel_dev"]) < 1e-3, c)
        out = subprocess.run([self.tool, "wheel-impedance", "--config", CI, "--wheel", "1", "--closed-form", "blocked"],
                             capture_output=True, text=True)
        check(out.returncode != 0 and "no resilient wheel" in out.stderr, out.stderr)

    def passage(self):
        out = WORK / "passage"
        s = self.run("passage", "--config", CI, "--duration", 0.05, "--out", out)
        check(s["steps"] == 5000, s)
        self.passage_dir = out
        # The soil loads of the first sample carry the tram's weight on both rails.
        loads = rows(out / "soil_loads.csv")
        total = sum(float(v) for k, v in loads[0].items() if k != "t_s")
        check(abs(total / (2 * s["weight_per_rail_n"]) - 1) < 0.01, f"{total} vs 2 x {s['weight_per_rail_n']}")
        # Full width, the defect on both rails (symmetric): a column per wheel (axleI_left/right), each the
        # half model's wheel; the soil loads a column per rail seat, the two seats' sum the half track's x 2. The defect on the left
        # rail only: the left wheel of the front axle takes the impact, its partner less.
        full_out = WORK / "passage_full"
        full = self.run("passage", "--config", CI, "--duration", 0.05, "--out", full_out, "--set", "track.width=full")
        check(full["width"] == "full" and len(full["wheels"]) == 2 * len(s["wheels"]), full)
        half_rows, full_rows = rows(out / "contact_forces.csv"), rows(full_out / "contact_forces.csv")
        check(len(half_rows) == len(full_rows), "as many contact-force rows at both widths")
        # (round-off drifts apart over the steps: 1e-8 of the peak in the unit test; bound 1e-6)
        peak = max(w["peak_force_n"] for w in s["wheels"])
        worst = max(abs(float(f[f"axle{a}_{rail}_force_n"]) - float(h[f"axle{a}_force_n"]))
                    for h, f in zip(half_rows, full_rows) for a in range(len(s["wheels"])) for rail in ("left", "right"))
        check(worst < 1e-6 * peak, f"full-width wheels vs the half model's: {worst} N")
        full_loads = rows(full_out / "soil_loads.csv")
        sleepers = [c for c in loads[0] if c != "t_s"]
        check(list(full_loads[0]) == ["t_s"] + [f"{c}_{seat}" for c in sleepers for seat in ("left", "right")],
              "a column per rail seat, left then right, per sleeper")
        worst = max(abs(float(full_loads[k][f"{c}_left"]) + float(full_loads[k][f"{c}_right"]) - float(loads[k][c]))
                    for k in range(len(loads)) for c in sleepers)
        check(worst < 1e-6 * max(abs(float(v)) for v in loads[0].values()), f"soil loads differ by {worst} N")
        self.passage_full_dir = full_out
        left = self.run("passage", "--config", CI, "--duration", 0.05, "--out", WORK / "passage_left",
                        "--set", "track.width=full", "--set", "unevenness.defect.rails=left",
                        "--set", "simulation.front_axle_start_m=-0.3")
        axle0 = {w["rail"]: w for w in left["wheels"] if w["axle"] == 0}
        check(axle0["left"]["peak_force_n"] > 2 * axle0["right"]["peak_force_n"], axle0)
        # the half track has one rail, standing for both: a defect on one rail is refused with the key
        bad = subprocess.run([self.tool, "passage", "--config", CI, "--duration", "0.05", "--out", str(WORK / "passage_bad"),
                              "--set", "unevenness.defect.rails=left"], capture_output=True, text=True)
        check(bad.returncode != 0 and "unevenness.defect.rails" in bad.stderr, bad.stderr)

    # ------------------------------------------------------------------ soil
    def soil(self):
        if not hasattr(self, "passage_dir"):
            self.passage()
        out = WORK / "soil"
        s = self.run("soil", "--config", CI, "--loads", self.passage_dir / "soil_loads.csv", "--out", out,
                     "--duration", 0.02)
        r = rows(out / "receivers.csv")
        check(len(r) == 21, f"{len(r)} receiver frames for 0.02 s at 1 kHz")
        check(all(math.isfinite(v["peak_abs_vz_m_s"]) for v in s["receiver_peaks"].values()), "finite peaks")
        # The full-width passage's loads per rail seat (symmetric): the same ground motion as the half chain's,
        # to the float soil's round-off (1.5e-6 of the 2 m peak over the CI scenario's 0.5 s, measured).
        full_out = WORK / "soil_full"
        full = self.run("soil", "--config", CI, "--set", "track.width=full", "--loads",
                        self.passage_full_dir / "soil_loads.csv", "--out", full_out, "--duration", 0.02)
        check(full["loads_per_sleeper"] == 2 and s["loads_per_sleeper"] == 1, (full["loads_per_sleeper"], s))
        fr = rows(full_out / "receivers.csv")
        cols = [c for c in r[0] if c != "t_s"]
        peak = max(abs(float(row[c])) for row in r for c in cols)
        worst = max(abs(float(a[c]) - float(b[c])) for a, b in zip(r, fr) for c in cols)
        check(len(fr) == len(r) and worst < 1e-4 * peak, f"full-width soil vs half: {worst} of a {peak} m/s peak")
        # Rail seat columns that do not pair up (a left seat without its right one, a pair of two sleepers) are refused.
        header = list(rows(self.passage_full_dir / "soil_loads.csv")[0])
        for bad_header in (header[:2], ["t_s", header[1], header[4]]):
            bad_path = WORK / "soil_loads_unpaired.csv"
            bad_path.write_text(",".join(bad_header) + "\n" + ",".join(["0"] * len(bad_header)) + "\n" +
                                ",".join(["0.0005"] + ["0"] * (len(bad_header) - 1)) + "\n")
            out = subprocess.run([self.tool, "soil", "--config", CI, "--set", "track.width=full", "--loads",
                                  str(bad_path), "--out", str(WORK / "soil_bad"), "--duration", "0.001"],
                                 capture_output=True, text=True)
            check(out.returncode != 0 and "come in pairs" in out.stderr, (bad_header, out.stderr))
        # Loads per rail seat on a half track's soil (or one per sleeper on a full one): refused, naming the key.
        for loads, width in ((self.passage_full_dir / "soil_loads.csv", "half"),
                             (self.passage_dir / "soil_loads.csv", "full")):
            out = subprocess.run([self.tool, "soil", "--config", CI, "--set", "track.width=" + width, "--loads",
                                  str(loads), "--out", str(WORK / "soil_bad"), "--duration", "0.001"],
                                 capture_output=True, text=True)
            check(out.returncode != 0 and "track.width is " + width in out.stderr, (width, out.stderr))
        # A loads file of another track layout (a column named after a sleeper the scenario does not have
        # there), or sampled too slowly for the mesh's f_max: refused with the reason.
        table = rows(self.passage_dir / "soil_loads.csv")
        header = list(table[0])
        moved = header[:2] + ["x_" + repr(float(header[2][2:]) + 0.3)] + header[3:]
        slow = WORK / "soil_loads_slow.csv"
        slow.write_text(",".join(header) + "\n" + "".join(
            ",".join([repr(0.05 * i)] + [table[0][c] for c in header[1:]]) + "\n" for i in range(5)))
        moved_path = WORK / "soil_loads_moved.csv"
        moved_path.write_text(",".join(moved) + "\n" + "".join(
            ",".join(row[c] for c in header) + "\n" for row in table[:5]))
        for loads, message in ((moved_path, "the loads come from another track layout"),
                               (slow, "below twice soil.mesh.f_max_hz")):
            out = subprocess.run([self.tool, "soil", "--config", CI, "--loads", str(loads), "--sleepers",
                                  str(self.passage_dir / "sleepers.csv"), "--out", str(WORK / "soil_bad"),
                                  "--duration", "0.001"], capture_output=True, text=True)
            check(out.returncode != 0 and message in out.stderr, (loads, out.stderr))

    def soil_bench(self):
        s = self.run("soil-bench", "throughput", "--nx", 16, "--ny", 8, "--nz", 4, "--steps", 3, "--repeat", 1,
                     "--precision", "float")
        # Each kernel side by side (soil.mesh.kernel: element, the baseline, and stencil).
        kernels = [k for k in ("element", "stencil") if k in s["float"]]
        check("element" in kernels, s["float"].keys())
        for k in kernels:
            check(s["float"][k]["threads_1"]["median_element_updates_per_s"] > 0, s["float"][k])
        # Without mpirun the rank bench runs on one rank: no cut, no halo, both timings of the same mesh.
        s = self.run("soil-bench", "ranks", "--config", CI, "--steps", 3, "--repeat", 1, "--precision", "float")
        check(s["ranks"] == 1 and s["halo_bytes_per_step_per_rank"] == [0], s)
        check(s["slab_cuts"][0] == 0 and s["slab_cuts"][-1] == s["mesh"]["nx"], s)
        check(s["one_rank_step_s"] > 0 and s["spread_step_s"] > 0, s)
        s = self.run("soil-bench", "column", "--precision", "float")
        check(abs(s["float"]["velocity_error"]) < 0.05, s)
        s = self.run("soil-bench", "damping", "--precision", "float")
        check(all(abs(m["relative_error"]) < 0.2 for m in s["modes"]), s)
        # The soil's voids and inclusions against CalculiX (an independent explicit FE code, same C3D8
        # elements, lumped mass and step): both central difference, so they agree to what CalculiX prints
        # (7 digits) and the load sampling, 3e-5 of each output node's peak measured; 1e-4 asserted. The
        # same box without its pit and block differs by ~100 x its peak at the pit's nodes.
        s = self.run("soil-bench", "void-peer", "--peer-duration", "0.015")
        check(s["difference_over_peak"] < 1e-4, s)
        check(s["difference_over_peak_without_inclusions"] > 0.1, s)
        check(s["inclusions"] == 2 and s["steps"] == 1500, s)

    def ssi_bench(self):
        # Coarse (two meshes, three boxes of a quarter model): no accuracy, but what must hold at any size:
        # a box with a fixed bottom is stiffer than the half-space, the less the larger it is; a finer mesh
        # is softer (the footing's edge); the references are the published ones.
        s = self.run("ssi-bench", "footing-static", "--mode", "vertical", "--h", "0.5,0.25", "--boxes", "2,3,4",
                     "--tolerance", 1e-4, "--threads", 1)
        v = s["vertical"]
        boxes = [r["normalised"] for r in v["box_sweep"]["runs"]]
        check(len(boxes) == 3 and boxes == sorted(boxes, reverse=True) and boxes[-1] > 0, boxes)
        meshes = [r["normalised"] for r in v["mesh_sweep"]["runs"]]
        check(len(meshes) == 2 and meshes[1] < meshes[0], meshes)
        check(0 < v["fe_normalised"] < boxes[-1], v["fe_normalised"])
        check(abs(v["gazetas_1991_normalised"] - 4.54) < 1e-9 and abs(v["pais_kausel_1988_normalised"] - 4.7) < 1e-9, v)
        # Embedded 0.75 B: the concrete box of implicit inclusions is as stiff as the rigid footing in each box (2 %), both
        # stiffer than the surface footing; a meshed box without embedment is refused.
        emb = {}
        for f in ("rigid", "meshed"):
            emb[f] = self.run("ssi-bench", "footing-static", "--mode", "vertical", "--h", "0.25,0.125", "--boxes", "2,3,4",
                              "--tolerance", 1e-4, "--threads", 1, "--embedment", 0.75, "--foundation", f,
                              "--wall", 0.25)["vertical"]
            check(emb[f]["embedment_m"] == 0.75 and emb[f]["fe_normalised"] > emb[f]["gazetas_1991_surface_normalised"],
                  emb[f])
        pairs = zip(emb["meshed"]["box_sweep"]["runs"], emb["rigid"]["box_sweep"]["runs"])
        check(all(abs(m["normalised"] / r["normalised"] - 1) < 0.02 for m, r in pairs), emb)
        out = subprocess.run([self.tool, "ssi-bench", "footing-static", "--foundation", "meshed"], capture_output=True,
                             text=True)
        check(out.returncode != 0 and "--embedment" in out.stderr, out.stderr)
        # The stiff-soil case on a small box and a short run (no accuracy: test_stiff_soil holds the 2 %): every
        # response point has its three components, the house carries soil, the figures are finite.
        s = self.run("ssi-bench", "stiff-soil", "--vs", 2500, "--margin", 6, "--depth", 8, "--duration", 0.1,
                     "--distance", 10, "--threads", 1)
        r = s["runs"][0]
        check(r["carried_soil_mass_kg"] > 0 and 0 < r["foundation_vz_two_way_vs_free_field_fit"] < 1, r)
        check(r["points"] and all(math.isfinite(c["two_way_vs_rigid_fit_of_free_field"])
                                  for p in r["points"] for c in p["components"].values()), r["points"])

    # ------------------------------------------------------------------ building
    def validate(self):
        # The quick model claims on the CI scenario: every claim has a verdict, the ones that agreed still agree.
        s = self.run("validate", "--config", CI, "--quick")
        check(len(s["claims"]) > 0 and s["agrees"] > 0 and s["regressions"] == [], s)
        check(s["agrees"] + s["differs"] + s["pending"] == len(s["claims"]), s)

    def building_modes(self):
        s = self.run("building-modes", "--config", CI, "--fmax", 30, "--vtk", WORK / "modes")
        # The VTK is in frame track: its points are the building frame's moved by the house's origin.
        check(s["vtk_frame"] == "track" and s["vtk_offset_m"][1] > 0, s.get("vtk_offset_m"))
        lines = pathlib.Path(s["vtk"]).read_text().splitlines()
        first = [float(v) for v in lines[lines.index(next(x for x in lines if x.startswith("POINTS"))) + 1].split()]
        b = self.run("building-modes", "--config", CI, "--fmax", 30, "--vtk", WORK / "modes_b", "--vtk-frame",
                     "building")
        lines_b = pathlib.Path(b["vtk"]).read_text().splitlines()
        first_b = [float(v) for v in lines_b[lines_b.index(next(x for x in lines_b if x.startswith("POINTS"))) + 1].split()]
        check(all(abs(first[i] - first_b[i] - s["vtk_offset_m"][i]) < 1e-9 for i in range(3)), (first, first_b))
        f = s["modal_frequencies_hz"] if "modal_frequencies_hz" in s else [m["frequency_hz"] for m in s["modes"]]
        check(f and all(x > 0 for x in f), s.keys())
        check(abs(s["mass"]["relative_difference"]) < 1e-9, s["mass"])

    def building_tf(self):
        s = self.run("building-tf", "--config", CI, "--duration", 2, "--fmax", 30, "--df", 0.5, "--csv",
                     WORK / "tf.csv")
        # Below the first mode the house moves with its foundation: |H| = 1.
        check(all(p["max_deviation_from_1_below_2hz"] < 0.05 for p in s["points"]), s["points"])

    def building_footprint(self):
        s = self.run("building-footprint", "--config", CI)
        check(len(s["points"]) == 21 * 15, len(s["points"]))
        self.footprint = [p["name"] for p in s["points"]]

    def building_response(self):
        if not hasattr(self, "footprint"):
            self.building_footprint()
        # The foundation moving rigidly and slowly (0.5 Hz vertical, 1 mm/s): the floors follow it.
        path = WORK / "footprint.csv"
        with open(path, "w") as f:
            f.write("time_s," + ",".join(f"{n}{c}" for n in self.footprint for c in ("_vx", "_vy", "_vz")) + "\n")
            for i in range(2001):
                t = i * 1e-3
                vz = 1e-3 * math.sin(2 * math.pi * 0.5 * t)
                f.write(repr(t) + ("," + "0,0," + repr(vz)) * len(self.footprint) + "\n")
        s = self.run("building-response", "--config", CI, "--footprint", path, "--out", WORK / "response.csv")
        for p in s["points"]:
            check(abs(p["peak_velocity_m_s"][2] / 1e-3 - 1) < 0.02, p)

    # ------------------------------------------------------------------ signal
    def metrics(self):
        path = WORK / "sine.csv"
        with open(path, "w") as f:
            f.write("t_s,vz\n")
            for i in range(4001):
                f.write(f"{i * 1e-3!r},{1e-3 * math.sin(2 * math.pi * 10 * i * 1e-3)!r}\n")
        s = self.run("metrics", "--csv", path, "--column", "vz")
        c = s["din4150_3"]["components"][0]
        check(abs(c["ppv_mm_s"] - 1.0) < 0.01 and abs(c["dominant_frequency_hz"] - 10) < 0.5, c)
        # Where the record was taken decides what is judged: nothing in the free field; a 10 Hz peak is
        # not assessable for a model resolving 8 Hz.
        s = self.run("metrics", "--csv", path, "--column", "vz", "--kind", "free_field")
        check(s["sensor"]["verdict"] == "not applicable" and s["din4150_3"]["verdict"] == "not applicable", s["sensor"])
        s = self.run("metrics", "--csv", path, "--column", "vz", "--resolved-hz", "8")
        check(s["sensor"]["verdict"] == "not assessable" and "10" in s["sensor"]["reason"], s["sensor"])
        # A list option's items are numbers within its range, or refused by name (no raw conversion error).
        for args, message in ((["--bands", "1,nan"], "--bands = '1,nan': 'nan' is not a number in"),
                              (["--bands", "1,x"], "'x' is not a number in"),
                              (["--kind", "roof"], "unknown sensor kind 'roof'")):
            out = subprocess.run([self.tool, "metrics", "--csv", str(path), "--column", "vz"] + args,
                                 capture_output=True, text=True)
            check(out.returncode != 0 and message in out.stderr, (args, out.stderr))
        # Every numeric option is finite and within its range, checked before it sizes anything: values that
        # would allocate without bound (channels, frequency steps, mesh counts, points) are refused at once.
        for args, message in ((["metrics", "--csv", str(path), "--column", "vz", "--vref", "nan"],
                               "--vref = 'nan' is not a finite number"),
                              (["decimator-check", "--channels", "99999999999"], "--channels = 99999999999 is outside"),
                              (["din-guides", "--step-hz", "1e-12"], "--step-hz = 1e-12 is outside its range"),
                              (["soil-bench", "throughput", "--nx", "100000"], "--nx = 100000 is outside"),
                              (["wheel-impedance", "--points", "1e9"], "--points = '1e9' is not a whole number"),
                              (["wheel-impedance", "--points", "1000000000"], "--points = 1000000000 is outside"),
                              (["track-bench", "--steps", "-5"], "--steps = -5 is outside")):
            t0 = time.monotonic()
            out = subprocess.run([self.tool] + args, capture_output=True, text=True, timeout=120)
            check(out.returncode != 0 and message in out.stderr and time.monotonic() - t0 < 30, (args, out.stderr))

    def din_check(self):
        s = self.run("din-check", "--rate", "1000")
        check(s["pass"], s)

    def din_guides(self):
        # DIN 4150-2 Table 1 (residential) and DIN 4150-3 Table 1 row 2: the standards' numbers.
        s = self.run("din-guides", "--step-hz", 5)
        day, night = s["din4150_2_residential"]["day"], s["din4150_2_residential"]["night"]
        check((day["a_u"], day["a_o"], day["a_r"]) == (0.15, 3.0, 0.07), day)
        check((night["a_u"], night["a_o"], night["a_r"]) == (0.1, 0.2, 0.05), night)
        curve = dict(zip(s["din4150_3_residential"]["frequency_hz"], s["din4150_3_residential"]["limit_mm_s"]))
        for f_hz, limit_mm_s in ((5, 5.0), (10, 5.0), (30, 10.0), (50, 15.0), (75, 17.5), (100, 20.0)):
            check(abs(curve[f_hz] - limit_mm_s) < 1e-12, (f_hz, curve[f_hz]))

    def decimator_check(self):
        s = self.run("decimator-check", "--channels", 4)
        check(s["passband_ripple_db"] < 0.1 and s["stopband_db"] < -60, s)


COMMANDS = {
    "config-check": "config_check", "receptance": "receptance", "insertion-loss": "insertion_loss",
    "moving-load": "moving_load",
    "track-bench": "track_bench", "vehicle-modes": "vehicle_modes", "wheel-impedance": "wheel_impedance",
    "passage": "passage", "soil": "soil", "soil-bench": "soil_bench", "building-modes": "building_modes",
    "building-tf": "building_tf", "building-response": "building_response",
    "building-footprint": "building_footprint", "metrics": "metrics", "din-check": "din_check", "din-guides": "din_guides",
    "decimator-check": "decimator_check",
    "ssi-bench": "ssi_bench", "validate": "validate",
}


def main(argv):
    parser = argparse.ArgumentParser(description="every railvib_tool subcommand on a small case")
    parser.add_argument("--tool")
    parser.add_argument("junit", nargs="?")
    options = parser.parse_args(argv[1:])
    sys.path.insert(0, str(ROOT / "scripts"))
    from railvib_paths import find_railvib_tool
    tool = options.tool or find_railvib_tool()
    listed = subprocess.run([tool, "--help"], capture_output=True, text=True).stdout
    registered = [line.split()[0] for line in listed.splitlines() if line.startswith("  ")]
    results = []
    missing = sorted(set(registered) - set(COMMANDS))
    if missing:
        results.append(("every command has a case", f"no case for: {', '.join(missing)}", 0.0))
    cases = Cases(tool)
    for command, method in COMMANDS.items():
        start = time.time()
        try:
            if command not in registered:
                raise Failure(f"{command} is not a railvib_tool command any more")
            getattr(cases, method)()
            error = None
        except (Failure, subprocess.TimeoutExpired, json.JSONDecodeError, KeyError, ValueError) as e:
            error = f"{type(e).__name__}: {e}"
        results.append((command, error, time.time() - start))
        print(f"[{'FAIL' if error else ' ok '}] {command} ({time.time() - start:.1f} s) {error or ''}", flush=True)
    if options.junit:
        suite = ET.Element("testsuite", name="tool_commands", tests=str(len(results)))
        for name, error, seconds in results:
            case = ET.SubElement(suite, "testcase", classname="ToolCommands", name=name, time=f"{seconds:.1f}")
            if error:
                ET.SubElement(case, "failure", message="failed").text = error
        pathlib.Path(options.junit).parent.mkdir(parents=True, exist_ok=True)
        ET.ElementTree(suite).write(options.junit, encoding="utf-8", xml_declaration=True)
    shutil.rmtree(WORK, ignore_errors=True)
    return 1 if any(e for _, e, _ in results) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
