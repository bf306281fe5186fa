"""The verdicts and sensor kinds of railvib/VibrationMetrics by value, for the scripts, read from the
message's own constants (VERDICT_*, KIND_*): the names the core gives them (signal::verdictName,
signal::sensorKindName). The message module is imported on first use (scripts start without ROS)."""
import functools


def _name(constant, prefix):
    """VERDICT_OK -> OK, VERDICT_NOT_APPLICABLE -> not applicable; KIND_FREE_FIELD -> free_field."""
    word = constant[len(prefix):]
    if prefix == "KIND_":
        return word.lower()
    return word if "_" not in word else word.lower().replace("_", " ")


@functools.lru_cache(maxsize=None)
def _table(prefix):
    import railvib.msg as rm
    m = rm.VibrationMetrics
    return {getattr(m, c): _name(c, prefix) for c in dir(m) if c.startswith(prefix)}


def verdict_name(value):
    """OK, WARN, ERROR, not applicable, not assessable ('?' for an unknown value)."""
    return _table("VERDICT_").get(value, "?")


def kind_name(value):
    """free_field, foundation, floor ('?' for an unknown value)."""
    return _table("KIND_").get(value, "?")


def kind_value(name):
    """The message's code of a kind name (free_field, foundation, floor); None for an unknown name."""
    return {n: v for v, n in _table("KIND_").items()}.get(name)


def kind_names():
    """The kind names, in the order of their codes."""
    return [n for _, n in sorted(_table("KIND_").items())]


def judged(value):
    """Whether a verdict judges (OK, WARN, ERROR), rather than saying a standard does not apply or cannot be judged."""
    return verdict_name(value) in ("OK", "WARN", "ERROR")
