#!/usr/bin/env python3
"""Compare two railvib bags message by message.

usage: compare_bags.py BAG_A BAG_B [--topics T1,T2,...] [--metrics TOPIC]

Every stream (default: the five sample streams) must hold the same number of
blocks, and block k of A must equal block k of B field by field, bit for bit
(header.seq is roscpp's own counter and is ignored). The metrics topic
(default /sensor_metrics) is compared too, sensor by sensor (the sensors'
messages interleave in arrival order), on the fields both message
definitions have: a field that only one side has (a message that gained a
field) is listed, not counted as a difference. Exit status 0 when nothing
differs, 1 otherwise; one line per topic on stdout.
"""
import argparse
import re
import sys

import rosbag

STREAMS = ["/contact_forces", "/soil_loads", "/surface_velocities", "/building_response", "/sensor_samples"]
METRICS = "/sensor_metrics"


def messages(bag_path, topic):
    with rosbag.Bag(str(bag_path)) as bag:
        return [m for _, m, _ in bag.read_messages(topics=[topic])]


def fields(msg):
    return list(getattr(msg, "__slots__", []))


def field_name(path):
    """A field's path without its indices: velocity_m_s[3]. -> velocity_m_s"""
    return re.sub(r"\[\d+\]", "", path).rstrip(".")


def field_peaks(msgs, path="", peaks=None):
    """The largest |value| of every floating-point field over the messages."""
    peaks = {} if peaks is None else peaks
    for m in msgs:
        slots = fields(m)
        if slots:
            for name in slots:
                field_peaks([getattr(m, name)], path + name + ".", peaks)
        elif isinstance(m, (list, tuple)):
            if m and isinstance(m[0], float):
                key = field_name(path)
                peaks[key] = max(peaks.get(key, 0.0), max(abs(x) for x in m))
            else:
                field_peaks(m, path, peaks)
        elif isinstance(m, float):
            key = field_name(path)
            peaks[key] = max(peaks.get(key, 0.0), abs(m))
    return peaks


def differences(a, b, path="", tolerance=None):
    """Paths where a and b differ (header.seq ignored), and fields only one side has. tolerance: None
    (bit for bit) or (relative tolerance, field peaks) for floating-point fields."""
    diffs, one_sided = [], set()
    slots_a, slots_b = fields(a), fields(b)
    if slots_a or slots_b:
        for name in slots_a:
            if name not in slots_b:
                one_sided.add(path + name)
        for name in slots_b:
            if name not in slots_a:
                one_sided.add(path + name)
        for name in slots_a:
            if name not in slots_b or (name == "seq" and path.endswith("header.")):
                continue
            d, o = differences(getattr(a, name), getattr(b, name), path + name + ".", tolerance)
            diffs += d
            one_sided |= o
        return diffs, one_sided
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        if len(a) != len(b):
            return [f"{path.rstrip('.')}: {len(a)} vs {len(b)} entries"], one_sided
        for i, (x, y) in enumerate(zip(a, b)):
            d, o = differences(x, y, f"{path.rstrip('.')}[{i}].", tolerance)
            diffs += d
            one_sided |= o
            if len(diffs) > 5:
                break
        return diffs, one_sided
    if tolerance is not None and isinstance(a, float) and isinstance(b, float):
        rel, peaks = tolerance
        bound = rel * peaks.get(field_name(path), 0.0)
        if abs(a - b) > bound:
            return [f"{path.rstrip('.')}: {a!r} vs {b!r} (bound {bound:.3g})"], one_sided
        return diffs, one_sided
    if a != b:
        return [f"{path.rstrip('.')}: {a!r} vs {b!r}"], one_sided
    return diffs, one_sided


def compare_topic(bag_a, bag_b, topic, relative_tolerance=None):
    """(ok, report line) for one topic; relative_tolerance: see the module's text (None: bit for bit)."""
    a, b = messages(bag_a, topic), messages(bag_b, topic)
    # Messages of several sensors on one topic (/sensor_metrics) interleave in the order they were
    # published, which depends on which input stream arrived first: each sensor's own sequence is
    # the result, so compare sensor by sensor (a stable sort keeps each sensor's order).
    if a and hasattr(a[0], "sensor_name"):
        a = sorted(a, key=lambda m: m.sensor_name)
        b = sorted(b, key=lambda m: getattr(m, "sensor_name", ""))
    if not a and not b:
        return False, f"{topic}: in neither bag"
    if len(a) != len(b):
        return False, f"{topic}: {len(a)} vs {len(b)} messages"
    one_sided = set()
    tolerance = None if relative_tolerance is None else (relative_tolerance, field_peaks(a))
    for k, (x, y) in enumerate(zip(a, b)):
        d, o = differences(x, y, tolerance=tolerance)
        one_sided |= o
        if d:
            return False, f"{topic}: message {k} differs: " + "; ".join(d[:5])
    extra = f" (fields on one side only, not compared: {', '.join(sorted(one_sided))})" if one_sided else ""
    same = "identical" if tolerance is None else f"equal within {relative_tolerance:g} of each field's peak"
    return True, f"{topic}: {len(a)} messages {same}{extra}"


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("bag_a")
    parser.add_argument("bag_b")
    parser.add_argument("--topics", default=",".join(STREAMS), help="streams to compare (comma-separated)")
    parser.add_argument("--metrics", default=METRICS, help="metrics topic ('' to skip)")
    parser.add_argument("--relative-tolerance", type=float, default=None,
                        help="floating-point fields within this fraction of the field's peak (default: bit for bit)")
    args = parser.parse_args(argv[1:])
    topics = [t for t in args.topics.split(",") if t] + ([args.metrics] if args.metrics else [])
    ok = True
    for topic in topics:
        same, line = compare_topic(args.bag_a, args.bag_b, topic, args.relative_tolerance)
        ok = ok and same
        print(line)
    print("identical" if ok else "DIFFERENT")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
