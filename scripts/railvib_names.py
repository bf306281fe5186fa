"""Topic, frame and output-point names of railvib, for the Python scripts and tests.

A mirror of include/railvib/common/names.hpp (the unit test Names.PythonMirrorAgrees
checks that every name here is the header's). Topics as recorded in a bag (with
the leading slash of the global namespace).
"""

TRACK_FRAME = "track"
BUILDING_FRAME = "building"

CONTACT_FORCES = "/contact_forces"
SOIL_LOADS = "/soil_loads"
SURFACE_VELOCITIES = "/surface_velocities"
BUILDING_RESPONSE = "/building_response"
SENSOR_SAMPLES = "/sensor_samples"
STREAMS = [CONTACT_FORCES, SOIL_LOADS, SURFACE_VELOCITIES, BUILDING_RESPONSE, SENSOR_SAMPLES]

SLEEPER_LAYOUT = "/sleeper_layout"
SURFACE_POINTS = "/surface_points"
BUILDING_POINTS = "/building_points"
SURFACE_SNAPSHOT = "/surface_snapshot"
SECTION_SNAPSHOT = "/section_snapshot"
SENSOR_METRICS = "/sensor_metrics"
SITE_MARKERS = "/visualization/site"
SURFACE_CLOUD = "/visualization/surface_velocity"
RECORDING_STATUS = "/railvib/recording"
SCENARIO = "/railvib/scenario"
CLOCK = "/clock"
DIAGNOSTICS = "/diagnostics"


def sensor_topic(sensor_name, what):
    """Per-sensor topics: /sensors/<name>/imu, .../velocity, .../metrics."""
    return f"/sensors/{sensor_name}/{what}"

RECEIVER_LINE_PREFIX = "line_y"
BUILDING_RESPONSE_FREE_FIELD_POINT = "bldg_response_point"


def sensor_frame(sensor_name):
    return "sensor_" + sensor_name


def tram_body_frame(body_name):
    return "tram/" + body_name


def footprint_point(i, j):
    return f"footprint_{i}_{j}"
