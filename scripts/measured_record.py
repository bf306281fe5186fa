#!/usr/bin/env python3
"""railvib import: a measured vibration record (CSV or WAV; acceleration or velocity) as the velocity
CSV every railvib tool reads (t_s and one column per channel, m/s), and its metrics.

usage: ./railvib import RECORD [--out VELOCITY.csv] [--quantity acceleration|velocity] [--unit UNIT]
                        [--channels NAME,...] [--time-column NAME] [--rate HZ] [--sensitivity S]
                        [--highpass-hz F] [--kind free_field|foundation|floor] [--period day|night]
                        [--no-metrics]

  RECORD          a CSV (a header row, then numbers: a time column and any channels, any names) or a
                  WAV (PCM 8/16/32 bit or float; one channel per axis)
  --quantity      what the channels hold (default acceleration)
  --unit          m_s2 | mm_s2 | g (acceleration), m_s | mm_s (velocity); default m_s2 or m_s
  --channels      the channels to take, comma-separated (CSV: column names; WAV: ch0, ch1, ...);
                  default: every column but the time column
  --time-column   the CSV's time column in seconds (default t_s, else t, time, time_s); without one,
                  --rate is required
  --rate          sample rate (Hz): a CSV without a time column; a WAV's own rate otherwise
  --sensitivity   WAV only, required: the physical value (in --unit) of a full-scale sample (1.0 of a
                  float WAV, 32768 of a 16-bit one), i.e. the recorder's range
  --highpass-hz   corner of the zero-phase high-pass (default 1.0 Hz for acceleration, 0 = none for
                  velocity); see below
  --kind, --period  passed to railvib_tool metrics: where the sensor stood, DIN 4150-2 period

Acceleration is integrated to velocity as vibration analysis does it, without a phase shift (so a
peak stays at its time and PPV is read where it happened): the mean is removed, a 4th-order
Butterworth high-pass at --highpass-hz is run forwards and backwards (scipy.signal.sosfiltfilt: zero
phase, magnitude squared, -6 dB at the corner, 1e-8 dB at 20 x the corner), the record is integrated
by the trapezoidal rule (scipy.integrate.cumulative_trapezoid), and the same high-pass removes the
drift of the integration constant and of any sensor offset. Before each filter pass the ends are
tapered to zero (half a Hann window over one period of the corner, at most a tenth of the record) and
the record is put between zeros, so the filter starts and ends at rest outside it: a measured record
starts and ends in ambient vibration, and an event there is attenuated. A corner of 1 Hz keeps the DIN 4150-2 KB
band (1-80 Hz) and DIN 4150-3's (1-100 Hz) whole; a lower one lets more drift through.

Every input is checked before anything is written: a readable file of the kind its content says (a
WAV's RIFF header), the channels and the time column by name (the ones there are listed), whole finite
numbers, a uniform time step (1 % at every row, as railvib's own CSV reader), a rate of 10 Hz to
1 MHz, a record of at least 1 s and 64 samples (a metric needs one), and values within the physical
bounds of config/haren.yaml's limits (10 m/s, 1e5 m/s^2).

Outputs: VELOCITY.csv (default RECORD_velocity.csv beside the record), VELOCITY.json (provenance:
the source, its quantity, unit, rate, channels, filter), and railvib_tool metrics' JSON on stdout
(PPV, KB_Fmax, dominant frequency, one-third octave levels, the verdicts that apply to --kind).
"""
import argparse
import csv
import json
import math
import pathlib
import subprocess
import sys

import numpy as np

from railvib_paths import find_railvib_tool

G_M_S2 = 9.80665  # standard gravity (ISO 80000-3)
UNITS = {  # unit -> (quantity, factor to SI)
    "m_s2": ("acceleration", 1.0), "mm_s2": ("acceleration", 1e-3), "g": ("acceleration", G_M_S2),
    "m_s": ("velocity", 1.0), "mm_s": ("velocity", 1e-3),
}
# config/haren.yaml limits: a value beyond is no ground vibration but a wrong unit or a broken file.
LIMITS_SI = {"acceleration": 1.0e5, "velocity": 10.0}
MIN_RATE_HZ, MAX_RATE_HZ = 10.0, 1.0e6
MIN_DURATION_S, MIN_SAMPLES = 1.0, 64
MAX_FILE_BYTES = 2 << 30
TIME_COLUMNS = ("t_s", "t", "time", "time_s")


class RecordError(Exception):
    """A record that cannot be imported: the message names the file and what is wrong."""


def _check_file(path):
    path = pathlib.Path(path)
    if not path.exists():
        raise RecordError(f"{path}: not found")
    if not path.is_file():
        raise RecordError(f"{path}: not a regular file")
    size = path.stat().st_size
    if size == 0:
        raise RecordError(f"{path}: empty")
    if size > MAX_FILE_BYTES:
        raise RecordError(f"{path}: {size} bytes, more than the {MAX_FILE_BYTES} a record may have")
    return path


def _uniform_rate(path, t):
    if len(t) < 2:
        raise RecordError(f"{path}: fewer than 2 samples")
    dt = np.diff(t)
    step = (t[-1] - t[0]) / (len(t) - 1)
    if not step > 0:
        raise RecordError(f"{path}: the time column does not increase")
    bad = np.flatnonzero(np.abs(dt - step) > 0.01 * step)
    if bad.size:
        i = int(bad[0])
        raise RecordError(f"{path}: time step {dt[i]:.6g} s between rows {i + 2} and {i + 3} differs from the "
                          f"mean step {step:.6g} s by more than 1 % (a record must be uniformly sampled)")
    return 1.0 / step


def read_csv(path, channels=None, time_column=None, rate_hz=None):
    """(rate_hz, {channel: samples}) of a CSV record."""
    path = _check_file(path)
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except UnicodeDecodeError:
        raise RecordError(f"{path}: not a text CSV file")
    if not rows or not rows[0]:
        raise RecordError(f"{path}: no header row")
    header = [h.strip() for h in rows[0]]
    if len(set(header)) != len(header):
        raise RecordError(f"{path}: repeated column names in the header {header}")
    data = []
    for n, row in enumerate(rows[1:], start=2):
        if not row or all(not c.strip() for c in row):
            continue
        if len(row) != len(header):
            raise RecordError(f"{path}: row {n} has {len(row)} values, the header {len(header)}")
        try:
            values = [float(c) for c in row]
        except ValueError:
            raise RecordError(f"{path}: row {n}: {row} is not all numbers")
        if not all(math.isfinite(v) for v in values):
            raise RecordError(f"{path}: row {n}: {row} holds a value that is not finite")
        data.append(values)
    if not data:
        raise RecordError(f"{path}: no data rows")
    table = np.array(data)
    if time_column is None:
        time_column = next((c for c in TIME_COLUMNS if c in header), None)
    elif time_column not in header:
        raise RecordError(f"{path}: no time column '{time_column}' (columns: {', '.join(header)})")
    if time_column is not None:
        if rate_hz is not None:
            raise RecordError(f"{path}: --rate given and a time column '{time_column}': one of them")
        rate_hz = _uniform_rate(path, table[:, header.index(time_column)])
    elif rate_hz is None:
        raise RecordError(f"{path}: no time column ({', '.join(TIME_COLUMNS)}) and no --rate")
    names = [h for h in header if h != time_column] if not channels else channels
    for c in names:
        if c not in header or c == time_column:
            raise RecordError(f"{path}: no channel '{c}' (columns: {', '.join(header)})")
    return rate_hz, {c: table[:, header.index(c)] for c in names}


def velocity_axes(path, axes=None):
    """A velocity CSV of ./railvib import as (axes, v [samples x 3] in m/s, rate_hz): axes are the
    record's channels taken as x, y, z of frame track ('-': not measured, zeros); default: three
    channels are x, y, z, one channel is z. The vertical is required (every comparison reads v_z)."""
    rate, channels = read_csv(path, time_column="t_s")
    names = list(channels)
    if axes is None:
        axes = names if len(names) == 3 else (["-", "-", names[0]] if len(names) == 1 else None)
        if axes is None:
            raise RecordError(f"{path}: {len(names)} channels ({', '.join(names)}): say which is x, y, z with --axes")
    if len(axes) != 3:
        raise RecordError(f"--axes {','.join(axes)}: three names (x, y, z), '-' for an axis not measured")
    for c in axes:
        if c != "-" and c not in channels:
            raise RecordError(f"--axes: {path} has no channel '{c}' ({', '.join(names)})")
    if axes[2] == "-":
        raise RecordError("--axes: the vertical (z) channel is needed")
    n = len(channels[axes[2]])
    v = np.column_stack([channels[c] if c != "-" else np.zeros(n) for c in axes])
    if not np.all(np.abs(v) <= LIMITS_SI["velocity"]):
        raise RecordError(f"{path}: a velocity beyond {LIMITS_SI['velocity']:g} m/s: not a velocity CSV in m/s")
    return list(axes), v, rate


def read_wav(path, sensitivity, channels=None):
    """(rate_hz, {chN: samples in the record's unit}) of a WAV record."""
    from scipy.io import wavfile
    path = _check_file(path)
    with open(path, "rb") as f:
        head = f.read(12)
    if len(head) < 12 or head[:4] not in (b"RIFF", b"RIFX") or head[8:12] != b"WAVE":
        raise RecordError(f"{path}: not a WAV file (no RIFF/WAVE header)")
    if sensitivity is None:
        raise RecordError(f"{path}: a WAV needs --sensitivity (the value of a full-scale sample in --unit)")
    try:
        rate, samples = wavfile.read(path)
    except (ValueError, OSError, EOFError) as e:
        raise RecordError(f"{path}: not a readable WAV file ({e})")
    if samples.dtype.kind == "f":
        scaled = samples.astype(float)
    elif samples.dtype == np.uint8:
        scaled = (samples.astype(float) - 128.0) / 128.0
    elif samples.dtype.kind == "i":
        scaled = samples.astype(float) / float(2 ** (8 * samples.dtype.itemsize - 1))
    else:
        raise RecordError(f"{path}: samples of type {samples.dtype} are not PCM or float")
    scaled = scaled.reshape(len(scaled), -1) * sensitivity
    available = [f"ch{i}" for i in range(scaled.shape[1])]
    names = channels or available
    for c in names:
        if c not in available:
            raise RecordError(f"{path}: no channel '{c}' (channels: {', '.join(available)})")
    return float(rate), {c: scaled[:, available.index(c)] for c in names}


def taper(n, rate_hz, corner_hz):
    """Weights that bring a record's ends smoothly to zero: half a Hann window over one period of the
    high-pass corner at each end (at most a tenth of the record), 1 elsewhere."""
    m = max(1, min(int(rate_hz / corner_hz), n // 10))
    w = np.ones(n)
    ramp = 0.5 * (1.0 - np.cos(np.pi * np.arange(m) / m))
    w[:m] = ramp
    w[n - m:] = ramp[::-1]
    return w


def highpass(x, rate_hz, corner_hz):
    """Zero-phase 4th-order Butterworth high-pass (run forwards and backwards) of a record whose mean is
    removed and whose ends are tapered to zero, between zeros over three periods of the corner: the
    filter starts and ends at rest, outside the record."""
    from scipy import signal
    sos = signal.butter(4, corner_hz, btype="highpass", fs=rate_hz, output="sos")
    x = np.asarray(x, dtype=float)
    pad = np.zeros(int(3.0 * rate_hz / corner_hz))
    y = signal.sosfiltfilt(sos, np.concatenate([pad, (x - np.mean(x)) * taper(len(x), rate_hz, corner_hz), pad]),
                           padtype=None)
    return y[len(pad):len(pad) + len(x)]


def to_velocity(x_si, rate_hz, quantity, highpass_hz):
    """Velocity (m/s) of a channel in SI units: integrated (acceleration) and high-passed (see above)."""
    from scipy.integrate import cumulative_trapezoid
    x = np.asarray(x_si, dtype=float) - np.mean(x_si)
    if quantity == "velocity":
        return highpass(x, rate_hz, highpass_hz) if highpass_hz > 0 else x
    if highpass_hz > 0:
        x = highpass(x, rate_hz, highpass_hz)
    v = cumulative_trapezoid(x, dx=1.0 / rate_hz, initial=0.0)
    v -= np.mean(v)
    return highpass(v, rate_hz, highpass_hz) if highpass_hz > 0 else v


def import_record(path, quantity="acceleration", unit=None, channels=None, time_column=None, rate_hz=None,
                  sensitivity=None, highpass_hz=None):
    """(rate_hz, {channel: velocity m/s}, provenance dict) of a measured record, every input checked."""
    if quantity not in ("acceleration", "velocity"):
        raise RecordError(f"--quantity {quantity}: acceleration or velocity")
    unit = unit or ("m_s2" if quantity == "acceleration" else "m_s")
    if unit not in UNITS or UNITS[unit][0] != quantity:
        raise RecordError(f"--unit {unit}: for {quantity} one of "
                          + ", ".join(u for u, (q, _) in UNITS.items() if q == quantity))
    for name, value in (("--rate", rate_hz), ("--sensitivity", sensitivity), ("--highpass-hz", highpass_hz)):
        if value is not None and not math.isfinite(value):
            raise RecordError(f"{name} {value}: not a finite number")
    if sensitivity is not None and not sensitivity > 0:
        raise RecordError(f"--sensitivity {sensitivity}: must be positive")
    if highpass_hz is None:
        highpass_hz = 1.0 if quantity == "acceleration" else 0.0
    if channels is not None and (not channels or any(not c for c in channels)):
        raise RecordError("--channels: one or more names, comma-separated")
    path = pathlib.Path(path)
    with open(_check_file(path), "rb") as f:
        is_wav = f.read(4) in (b"RIFF", b"RIFX")
    if is_wav or path.suffix.lower() == ".wav":
        if time_column is not None or rate_hz is not None:
            raise RecordError(f"{path}: a WAV carries its own rate (no --rate, no --time-column)")
        rate_hz, raw = read_wav(path, sensitivity, channels)
        kind = "wav"
    else:
        if sensitivity is not None:
            raise RecordError(f"{path}: --sensitivity is for WAV records (a CSV holds values in --unit)")
        rate_hz, raw = read_csv(path, channels, time_column, rate_hz)
        kind = "csv"
    if not MIN_RATE_HZ <= rate_hz <= MAX_RATE_HZ:
        raise RecordError(f"{path}: sample rate {rate_hz:.6g} Hz outside [{MIN_RATE_HZ:g}, {MAX_RATE_HZ:g}] Hz")
    samples = len(next(iter(raw.values())))
    duration = samples / rate_hz
    if samples < MIN_SAMPLES or duration < MIN_DURATION_S:
        raise RecordError(f"{path}: {samples} samples, {duration:.3g} s: too short for a metric "
                          f"(at least {MIN_SAMPLES} samples and {MIN_DURATION_S:g} s)")
    if highpass_hz < 0 or (highpass_hz > 0 and highpass_hz >= 0.2 * rate_hz):
        raise RecordError(f"--highpass-hz {highpass_hz}: 0 (none) or above 0 and below a fifth of the rate "
                          f"({0.2 * rate_hz:.6g} Hz)")
    factor = UNITS[unit][1]
    bound = LIMITS_SI[quantity]
    velocity = {}
    for name, x in raw.items():
        x_si = x * factor
        peak = float(np.max(np.abs(x_si)))
        if not math.isfinite(peak) or peak > bound:
            raise RecordError(f"{path}: channel '{name}' peaks at {peak:.6g} SI units, beyond the {bound:g} "
                              f"{'m/s^2' if quantity == 'acceleration' else 'm/s'} of any ground vibration "
                              f"(a wrong --unit or --sensitivity?)")
        velocity[name] = to_velocity(x_si, rate_hz, quantity, highpass_hz)
    provenance = {"source": str(path.resolve()), "format": kind, "quantity": quantity, "unit": unit,
                  "rate_hz": rate_hz, "samples": samples, "channels": list(velocity),
                  "sensitivity": sensitivity, "highpass_hz": highpass_hz,
                  "filter": ("mean removed, 4th-order Butterworth high-pass run forwards and backwards "
                             "(zero phase) before and after trapezoidal integration" if quantity == "acceleration"
                             else ("mean removed" + (", zero-phase 4th-order Butterworth high-pass"
                                                     if highpass_hz > 0 else "")))}
    return rate_hz, velocity, provenance


def write_velocity_csv(out, rate_hz, velocity, provenance):
    out = pathlib.Path(out)
    if out.is_dir():
        raise RecordError(f"{out}: is a directory (give a file name with --out)")
    n = len(next(iter(velocity.values())))
    columns = [np.arange(n) / rate_hz] + list(velocity.values())
    np.savetxt(out, np.column_stack(columns), delimiter=",", header=",".join(["t_s"] + list(velocity)),
               comments="", fmt="%.9g")
    out.with_suffix(".json").write_text(json.dumps({**provenance, "velocity_csv": str(out.resolve()),
                                                    "velocity_unit": "m_s"}, indent=2) + "\n")
    return out


def main(argv):
    ap = argparse.ArgumentParser(prog="./railvib import", description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("record")
    ap.add_argument("--out")
    ap.add_argument("--quantity", default="acceleration")
    ap.add_argument("--unit")
    ap.add_argument("--channels")
    ap.add_argument("--time-column")
    ap.add_argument("--rate", type=float)
    ap.add_argument("--sensitivity", type=float)
    ap.add_argument("--highpass-hz", type=float)
    ap.add_argument("--kind", default="foundation", choices=["free_field", "foundation", "floor"])
    ap.add_argument("--period", default="day", choices=["day", "night"])
    ap.add_argument("--no-metrics", action="store_true")
    a = ap.parse_args(argv[1:])
    try:
        channels = a.channels.split(",") if a.channels is not None else None
        rate, velocity, provenance = import_record(a.record, a.quantity, a.unit, channels, a.time_column, a.rate,
                                                   a.sensitivity, a.highpass_hz)
        out = pathlib.Path(a.out) if a.out else pathlib.Path(a.record).with_name(
            pathlib.Path(a.record).stem + "_velocity.csv")
        write_velocity_csv(out, rate, velocity, provenance)
    except RecordError as e:
        print(f"railvib import: error: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"railvib import: error: {e}", file=sys.stderr)
        return 2
    print(f"railvib import: {out} ({len(velocity)} channel(s), {rate:g} Hz, "
          f"{provenance['samples'] / rate:.3f} s, velocity in m/s)", file=sys.stderr)
    if a.no_metrics:
        return 0
    tool = find_railvib_tool()
    if not tool:
        print("railvib import: railvib_tool not found (./railvib setup): no metrics", file=sys.stderr)
        return 1
    r = subprocess.run([tool, "metrics", "--csv", str(out), "--column", ",".join(velocity), "--kind", a.kind,
                        "--period", a.period], capture_output=True, text=True)
    sys.stdout.write(r.stdout)
    sys.stderr.write(r.stderr)
    return r.returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv))
