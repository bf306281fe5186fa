"""The contract of the non-stream messages (metrics, snapshots, transforms) for the Python readers.

The same rules as the core's (src/common/message_contract.cpp, which the recorder and the scene
visualiser apply): a metrics message, a snapshot or a transform stands alone, so anything a foreign
publisher puts on those topics is checked before it is shown or trusted. Each function returns None
for a valid message, else the reason, naming the topic and the field. Both implementations are held
to one table of cases (test/data/message_contract_cases.json).

Messages are read by attribute (rospy messages, or anything with the same fields)."""
import math

MAX_THIRD_OCTAVE_BANDS = 64
MAX_SNAPSHOT_VALUES = 16000000
MAX_TRANSLATION_M = 1.0e6
QUATERNION_NORM_TOLERANCE = 1.0e-3
# limits.velocity_m_s when the scenario does not set it (include/railvib/common/stream_contract.hpp).
DEFAULT_VELOCITY_LIMIT_M_S = 10.0
VERDICT_NAMES = "OK, WARN, ERROR, NOT_APPLICABLE, NOT_ASSESSABLE"


class Refused(Exception):
    pass


def _finite_within(topic, field, value, lo, hi, why=""):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise Refused(f"topic {topic}: {field} = {value!r}: not a number")
    if not (math.isfinite(v) and lo <= v <= hi):
        raise Refused(f"topic {topic}: {field} = {v:g}: must be finite within [{lo:g}, {hi:g}]"
                      + (f" ({why})" if why else ""))
    return v


def _code(topic, field, value, largest, meaning):
    if not (isinstance(value, int) and 0 <= value <= largest):
        raise Refused(f"topic {topic}: {field} = {value}: not one of 0..{largest} ({meaning})")


def _at_most(value, maximum):
    """Running maxima are taken over the same samples as the current values: equal within rounding."""
    return value <= maximum * (1.0 + 1e-9) + 1e-15


def _values_within(topic, field, values, bound):
    for i, v in enumerate(values):
        if not abs(float(v)) <= bound:  # also true for NaN
            raise Refused(f"topic {topic}: {field}[{i}] = {float(v):g}: must be finite with magnitude <= {bound:g} m/s "
                          "(limits.velocity_m_s)")


def _check(fn, *args):
    try:
        fn(*args)
    except Refused as e:
        return str(e)
    return None


def _metrics(topic, m, velocity, known_sensors):
    if not m.sensor_name:
        raise Refused(f"topic {topic}: sensor_name is empty")
    if known_sensors and m.sensor_name not in known_sensors:
        raise Refused(f"topic {topic}: sensor_name '{m.sensor_name}' is not a sensor of the scenario "
                      f"({', '.join(known_sensors)})")
    _code(topic, "kind", m.kind, 2, "free field, foundation, floor")
    _code(topic, "governing_component", m.governing_component, 2, "x, y, z")
    for field in ("din4150_2_verdict", "din4150_3_verdict", "verdict"):
        _code(topic, field, getattr(m, field), 4, VERDICT_NAMES)
    why_v = f"limits.velocity_m_s = {velocity:g} per component"
    _finite_within(topic, "resolved_hz", m.resolved_hz, 0.0, 1e5, "a frequency in Hz")
    kb_bound = 2.0 * 1e3 * velocity  # KB_F in mm/s, with room for the weighting filter's overshoot
    kb_f = _finite_within(topic, "kb_f", m.kb_f, 0.0, kb_bound, "2 x limits.velocity_m_s in mm/s")
    kb_f_max = _finite_within(topic, "kb_f_max", m.kb_f_max, 0.0, kb_bound, "2 x limits.velocity_m_s in mm/s")
    if not _at_most(kb_f, kb_f_max):
        raise Refused(f"topic {topic}: kb_f = {kb_f:g} exceeds its running maximum kb_f_max = {kb_f_max:g}")
    ppv = _finite_within(topic, "ppv_m_s", m.ppv_m_s, 0.0, math.sqrt(3.0) * velocity, "sqrt(3) x " + why_v)
    for field in ("ppv_vertical_m_s", "governing_ppv_m_s"):
        _finite_within(topic, field, getattr(m, field), 0.0, velocity, why_v)
    for field in ("ppv_vertical_m_s", "governing_ppv_m_s"):
        if not _at_most(float(getattr(m, field)), ppv):
            raise Refused(f"topic {topic}: {field} = {float(getattr(m, field)):g} exceeds the vector peak "
                          f"ppv_m_s = {ppv:g} (a component's peak cannot)")
    _finite_within(topic, "dominant_frequency_hz", m.dominant_frequency_hz, 0.0, 1e5, "a frequency in Hz")
    _finite_within(topic, "din4150_3_limit_m_s", m.din4150_3_limit_m_s, 0.0, velocity, why_v)
    # Bags recorded before the message carried the guide values have none: 0, as the reports read them.
    a_u, a_o = (_finite_within(topic, f, getattr(m, f, 0.0), 0.0, 1e3, "a DIN 4150-2 guide value")
                for f in ("din4150_2_a_u", "din4150_2_a_o"))
    _finite_within(topic, "din4150_2_a_r", getattr(m, "din4150_2_a_r", 0.0), 0.0, 1e3, "a DIN 4150-2 guide value")
    if a_u > a_o:
        raise Refused(f"topic {topic}: din4150_2_a_u = {a_u:g} exceeds din4150_2_a_o = {a_o:g} "
                      "(DIN 4150-2 Table 1: A_u < A_o)")
    centres, levels = list(m.third_octave_center_hz), list(m.third_octave_level_db)
    if len(centres) > MAX_THIRD_OCTAVE_BANDS:
        raise Refused(f"topic {topic}: third_octave_center_hz has {len(centres)} bands; at most {MAX_THIRD_OCTAVE_BANDS}")
    if len(levels) != len(centres):
        raise Refused(f"topic {topic}: third_octave_level_db has {len(levels)} values for {len(centres)} band centres")
    for b, c in enumerate(centres):
        c = float(c)
        if not (math.isfinite(c) and 0.0 < c <= 1e5) or (b > 0 and c <= float(centres[b - 1])):
            raise Refused(f"topic {topic}: third_octave_center_hz[{b}] = {c:g}: band centres must be finite, "
                          "positive (Hz) and increasing")
    level_bound_db = 20.0 * math.log10(velocity / 1e-9) + 20.0  # re 1e-9 m/s (ISO 1683), +20 dB
    for b, level in enumerate(levels):
        level = float(level)
        if math.isnan(level) or level > level_bound_db:  # -inf: nothing in the band yet
            raise Refused(f"topic {topic}: third_octave_level_db[{b}] = {level:g}: must be a level in dB re 1e-9 m/s, "
                          f"at most {level_bound_db:g} (limits.velocity_m_s + 20 dB)")


def metrics_problem(topic, msg, velocity_limit_m_s=DEFAULT_VELOCITY_LIMIT_M_S, known_sensors=()):
    """Why a railvib/VibrationMetrics message is refused, or None."""
    return _check(_metrics, topic, msg, float(velocity_limit_m_s), list(known_sensors))


def velocity_problem(topic, vector_m_s, velocity_limit_m_s=DEFAULT_VELOCITY_LIMIT_M_S):
    """Why a sensor's velocity sample (geometry_msgs/Vector3: x, y, z in m/s) is refused, or None."""
    bound = float(velocity_limit_m_s)
    for axis in "xyz":
        v = float(getattr(vector_m_s, axis))
        if not abs(v) <= bound:  # also true for NaN
            return (f"topic {topic}: vector.{axis} = {v:g}: must be finite with magnitude <= {bound:g} m/s "
                    "(limits.velocity_m_s)")
    return None


def _spacing(topic, field, value):
    _finite_within(topic, field, value, 1e-9, MAX_TRANSLATION_M, "a grid spacing in m, positive")


def _horizontal(topic, m, count, velocity):
    """The horizontal fields: both empty (a vertical-only snapshot, or a bag recorded before they
    existed) or both laid out as the vertical."""
    fields = {f: list(getattr(m, f, []) or []) for f in ("velocity_x_m_s", "velocity_y_m_s")}
    if not any(fields.values()):
        return
    for field, values in fields.items():
        if len(values) != count:
            raise Refused(f"topic {topic}: {field} has {len(values)} values, not {count} as vertical_velocity_m_s "
                          "(or both horizontal fields empty)")
        _values_within(topic, field, values, velocity)


def _surface(topic, m, velocity):
    nx, ny, values = int(m.nx), int(m.ny), m.vertical_velocity_m_s
    if nx < 1 or ny < 1 or nx * ny > MAX_SNAPSHOT_VALUES:
        raise Refused(f"topic {topic}: a {nx} x {ny} grid: nx and ny must be >= 1 with nx x ny <= {MAX_SNAPSHOT_VALUES}")
    if len(values) != nx * ny:
        raise Refused(f"topic {topic}: vertical_velocity_m_s has {len(values)} values, not nx x ny = {nx} x {ny} = "
                      f"{nx * ny}")
    for field in ("origin_x_m", "origin_y_m"):
        _finite_within(topic, field, getattr(m, field), -MAX_TRANSLATION_M, MAX_TRANSLATION_M, "frame track")
    for field in ("spacing_x_m", "spacing_y_m"):
        _spacing(topic, field, getattr(m, field))
    _values_within(topic, "vertical_velocity_m_s", values, velocity)
    _horizontal(topic, m, nx * ny, velocity)


def surface_snapshot_problem(topic, msg, velocity_limit_m_s=DEFAULT_VELOCITY_LIMIT_M_S):
    """Why a railvib/SurfaceSnapshot message is refused, or None."""
    return _check(_surface, topic, msg, float(velocity_limit_m_s))


def _section(topic, m, velocity):
    ny, depths, values = int(m.ny), list(m.depth_m), m.vertical_velocity_m_s
    rows = len(depths)
    if ny < 1 or rows < 1 or rows * ny > MAX_SNAPSHOT_VALUES:
        raise Refused(f"topic {topic}: a section of {rows} depths (depth_m) x ny = {ny} columns: both must be >= 1 "
                      f"with their product <= {MAX_SNAPSHOT_VALUES}")
    if len(values) != rows * ny:
        raise Refused(f"topic {topic}: vertical_velocity_m_s has {len(values)} values, not depths x ny = {rows} x {ny} = "
                      f"{rows * ny}")
    _finite_within(topic, "x_m", m.x_m, -MAX_TRANSLATION_M, MAX_TRANSLATION_M, "frame track")
    _finite_within(topic, "origin_y_m", m.origin_y_m, -MAX_TRANSLATION_M, MAX_TRANSLATION_M, "frame track")
    _spacing(topic, "spacing_y_m", m.spacing_y_m)
    for r, d in enumerate(depths):
        d = float(d)
        if not (math.isfinite(d) and 0.0 <= d <= MAX_TRANSLATION_M) or (r > 0 and d <= float(depths[r - 1])):
            raise Refused(f"topic {topic}: depth_m[{r}] = {d:g}: depths must be finite, >= 0 (m below the surface) "
                          "and increasing")
    _values_within(topic, "vertical_velocity_m_s", values, velocity)
    _horizontal(topic, m, rows * ny, velocity)


def section_snapshot_problem(topic, msg, velocity_limit_m_s=DEFAULT_VELOCITY_LIMIT_M_S):
    """Why a railvib/SectionSnapshot message is refused, or None."""
    return _check(_section, topic, msg, float(velocity_limit_m_s))


def _transform(topic, parent, child, translation, rotation):
    if not parent or not child:
        raise Refused(f"topic {topic}: a transform '{parent}' -> '{child}' with an empty frame name")
    what = f"topic {topic}: transform '{parent}' -> '{child}': "
    if parent == child:
        raise Refused(what + "a frame cannot be its own parent")
    for axis, v in zip("xyz", translation):
        if not abs(float(v)) <= MAX_TRANSLATION_M:
            raise Refused(what + f"translation.{axis} = {float(v):g} m: must be finite within {MAX_TRANSLATION_M:g} m")
    for axis, v in zip("xyzw", rotation):
        if not math.isfinite(float(v)):
            raise Refused(what + f"rotation.{axis} = {float(v):g}: must be finite")
    norm = math.sqrt(sum(float(v) ** 2 for v in rotation))
    if not abs(norm - 1.0) <= QUATERNION_NORM_TOLERANCE:
        raise Refused(what + f"rotation quaternion has norm {norm:g}: not a rotation (|q| = 1 within "
                      f"{QUATERNION_NORM_TOLERANCE:g})")


def transform_problem(topic, parent, child, translation_m, rotation_xyzw):
    """Why one transform is refused, or None."""
    return _check(_transform, topic, parent, child, list(translation_m), list(rotation_xyzw))


def tf_message_problem(topic, msg):
    """Why a tf2_msgs/TFMessage is refused (its first bad transform), or None."""
    for t in msg.transforms:
        tr, q = t.transform.translation, t.transform.rotation
        problem = transform_problem(topic, t.header.frame_id, t.child_frame_id, (tr.x, tr.y, tr.z),
                                    (q.x, q.y, q.z, q.w))
        if problem:
            return problem
    return None
