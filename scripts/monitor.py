#!/usr/bin/env python3
"""Live vibration monitor of railvib's virtual sensors (one window, updated as samples arrive).

For each virtual sensor, one row of four plots:
  - velocity, three components in the sensor's frame (mm/s), over a sliding window of simulation time;
  - the running DIN 4150-2 KB_F(t), with the guide values A_u and A_o the sensor's messages carry;
  - the governing peak velocity (DIN 4150-3) at its dominant frequency, against the DIN 4150-3
    residential guideline curve (printed by the core: `railvib_tool din-guides`);
  - the one-third-octave velocity levels (dB re 1e-9 m/s).
The figure title says the simulation time, the samples received and each sensor's live verdict.

    ./railvib monitor [--sensors a,b] [--window-s 5] [--screenshot PNG --screenshot-after S] [--exit-after S]

Start it next to `./railvib run` (or `roslaunch railvib haren.launch`) or a replay
(`roslaunch railvib replay.launch bag:=FILE`). Without --sensors it discovers the sensors from the
published /sensors/<name>/velocity topics, waiting until some appear. A looping replay restarts
simulation time at 0: the monitor sees each sensor's stamps jump back and clears that sensor's
plots. A message that breaks the message contract (scripts/railvib_contracts.py: a NaN, a metrics
message naming another sensor, codes out of their range; a foreign publisher's) is not shown, and
said. On exit (window closed, Ctrl+C, SIGTERM or --exit-after) it prints one JSON line with the
velocity samples, metrics messages and refused messages received per sensor.
"""
import argparse
import collections
import json
import math
import os
import signal
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import railvib_contracts  # noqa: E402
import railvib_names as names  # noqa: E402
import railvib_plots  # noqa: E402
import railvib_verdicts  # noqa: E402

# Velocity components in the sensor's frame; the colours are also what test_monitor.py looks for.
COMPONENT_NAMES = railvib_plots.COMPONENT_NAMES
COMPONENT_COLOURS = railvib_plots.COMPONENT_COLOURS
KB_F_COLOUR = "#6a3d9a"
A_U_COLOUR = "#e08214"
A_O_COLOUR = "#b2182b"
BAR_COLOUR = railvib_plots.BAR_COLOUR
# VibrationMetrics.VERDICT_OK / _WARN / _ERROR / _NOT_APPLICABLE / _NOT_ASSESSABLE (names: railvib_verdicts).
VERDICT_COLOURS = {0: "#1a7a3a", 1: "#c77800", 2: "#c0141c", 3: "#555555", 4: "#7a4fa0", None: "#555555"}
VELOCITY_TYPE = "geometry_msgs/Vector3Stamped"
LAYOUT_PREFIX = "monitor: axes "


_log_lock = threading.Lock()


def log(text):
    # One write per line under a lock: the ROS callbacks of several sensors log from their own threads.
    with _log_lock:
        sys.stdout.write("monitor: " + text + "\n")
        sys.stdout.flush()


class SensorBuffers:
    """What the ROS callbacks of one sensor collected; every field is guarded by `lock`."""

    def __init__(self):
        self.lock = threading.Lock()
        self.velocity = collections.deque()  # (t_s, vx_mm_s, vy_mm_s, vz_mm_s) within the window
        self.kb_f = collections.deque()  # (t_s, KB_F) within the window
        self.latest_metrics = None
        self.velocity_count = 0  # over the whole run (every pass): proves nothing was lost
        self.metrics_count = 0
        self.passes = 0  # runs of increasing simulation time (a looping replay starts a new one)
        self.last_velocity_t_s = None
        self.last_metrics_t_s = None
        self.refused_count = 0  # messages that broke the message contract (a foreign publisher): not shown


class Monitor:
    def __init__(self, options):
        self.options = options
        self.window_s = options.window_s
        self.sensors = collections.OrderedDict()  # name -> SensorBuffers
        self.sensors_lock = threading.Lock()
        self.subscribers = []
        self.status = "waiting for the ROS master"
        self.newest_pass = 0  # the highest pass number any sensor has started (guarded by sensors_lock)
        self.stopping = threading.Event()
        # The DIN 4150-3 guideline as the report draws it (scripts/railvib_plots.py, from the core).
        self.guidelines = railvib_plots.load_guidelines()
        if self.guidelines.error:
            print("monitor: warning: no DIN 4150-3 guideline line: " + self.guidelines.error, file=sys.stderr,
                  flush=True)
        # The topic pattern comes from railvib_names, with a placeholder in the sensor's place.
        placeholder = "\0"
        self.topic_prefix, self.topic_suffix = names.sensor_topic(placeholder, "velocity").split(placeholder)

    # ------------------------------------------------------------------ ROS side (threads)
    def add_sensor(self, name):
        import rospy
        from geometry_msgs.msg import Vector3Stamped
        import railvib.msg as railvib_msgs

        with self.sensors_lock:
            if name in self.sensors:
                return
            self.sensors[name] = SensorBuffers()
        # Unbounded queues (queue_size=None): a slow redraw delays the callbacks, it never drops a sample.
        self.subscribers.append(rospy.Subscriber(names.sensor_topic(name, "velocity"), Vector3Stamped,
                                                 self.on_velocity, callback_args=name, queue_size=None))
        self.subscribers.append(rospy.Subscriber(names.sensor_topic(name, "metrics"), railvib_msgs.VibrationMetrics,
                                                 self.on_metrics, callback_args=name, queue_size=None))
        log(f"subscribed to sensor {name}")

    def sensor_from_topic(self, topic, topic_type):
        if (topic_type != VELOCITY_TYPE or not topic.startswith(self.topic_prefix)
                or not topic.endswith(self.topic_suffix)):
            return None
        name = topic[len(self.topic_prefix):len(topic) - len(self.topic_suffix)]
        return name if name and "/" not in name else None

    def ros_thread(self):
        """Waits for the master, starts the node and finds the sensors; off the GUI thread so the
        window opens (and says what it waits for) at once."""
        import rosgraph
        import rospy

        master = rosgraph.Master("/railvib_monitor")
        log(f"waiting for the ROS master at {rosgraph.get_master_uri()}")
        while not self.stopping.is_set():
            try:
                master.getPid()
                break
            except Exception:  # not up yet
                self.stopping.wait(0.5)
        if self.stopping.is_set():
            return
        rospy.init_node("railvib_monitor", anonymous=True, disable_signals=True)
        if self.options.sensors:
            for name in self.options.sensors:
                self.add_sensor(name)
            self.status = ""
            return
        pattern = names.sensor_topic("<name>", "velocity")
        self.status = f"waiting for sensors ({pattern} topics)"
        log(self.status)
        # Keep polling after the first sensors: a sensor node started later adds its rows.
        master_lost = False
        while not self.stopping.is_set():
            try:
                topics = rospy.get_published_topics()
                master_lost = False
            except Exception as error:  # the master went away (the run ended); try again, say it once
                if not master_lost:
                    log(f"cannot list the topics ({error}); retrying")
                master_lost = True
                topics = []
            for topic, topic_type in sorted(topics):
                name = self.sensor_from_topic(topic, topic_type)
                if name:
                    self.add_sensor(name)
            with self.sensors_lock:
                found = bool(self.sensors)
            if found:
                self.status = ""
            self.stopping.wait(2.0 if found else 0.5)

    def trim(self, buffer, newest_t_s):
        while buffer and buffer[0][0] < newest_t_s - self.window_s:
            buffer.popleft()

    def refuse(self, buffers, problem):
        """A message that breaks the contract is not shown; the first of each sensor and every 100th is said."""
        with buffers.lock:
            buffers.refused_count += 1
            count = buffers.refused_count
        if count == 1 or count % 100 == 0:
            log(f"refused {count} message(s) so far, not shown: {problem}")

    def on_velocity(self, msg, name):
        t_s = msg.header.stamp.to_sec()
        buffers = self.sensors[name]
        topic = names.sensor_topic(name, "velocity")
        problem = railvib_contracts.velocity_problem(topic, msg.vector)
        if problem or not math.isfinite(t_s):
            self.refuse(buffers, problem or f"topic {topic}: stamp {t_s} is not a time")
            return
        restarted_from = None
        with buffers.lock:
            if buffers.last_velocity_t_s is None or t_s < buffers.last_velocity_t_s:
                # Simulation time went back (a looping replay): a new pass, the old samples go.
                if buffers.last_velocity_t_s is not None:
                    restarted_from = buffers.last_velocity_t_s
                buffers.velocity.clear()
                buffers.passes += 1
                new_pass = buffers.passes
            buffers.last_velocity_t_s = t_s
            buffers.velocity_count += 1
            buffers.velocity.append((t_s, msg.vector.x * 1e3, msg.vector.y * 1e3, msg.vector.z * 1e3))
            self.trim(buffers.velocity, t_s)
        if restarted_from is not None:
            # Said once per pass (by the first sensor to start it), not once per sensor.
            with self.sensors_lock:
                first = new_pass > self.newest_pass
                self.newest_pass = max(self.newest_pass, new_pass)
            if first:
                log(f"pass {new_pass}: simulation time went back from {restarted_from:.3f} s to {t_s:.3f} s "
                    f"({name} first): plots cleared")

    def on_metrics(self, msg, name):
        t_s = msg.header.stamp.to_sec()
        buffers = self.sensors[name]
        # The message names its sensor: it must be the one whose topic it came on.
        problem = railvib_contracts.metrics_problem(names.sensor_topic(name, "metrics"), msg,
                                                    known_sensors=[name])
        if problem:
            self.refuse(buffers, problem)
            return
        with buffers.lock:
            if buffers.last_metrics_t_s is not None and t_s < buffers.last_metrics_t_s:
                buffers.kb_f.clear()
            buffers.last_metrics_t_s = t_s
            buffers.metrics_count += 1
            buffers.latest_metrics = msg
            buffers.kb_f.append((t_s, msg.kb_f))
            self.trim(buffers.kb_f, t_s)

    def counts(self):
        result = {"velocity_samples": {}, "metrics_messages": {}, "passes": {}, "window_velocity_samples": {},
                  "refused_messages": {}}
        with self.sensors_lock:
            items = list(self.sensors.items())
        for name, buffers in items:
            with buffers.lock:
                result["velocity_samples"][name] = buffers.velocity_count
                result["metrics_messages"][name] = buffers.metrics_count
                result["passes"][name] = buffers.passes
                result["window_velocity_samples"][name] = len(buffers.velocity)
                result["refused_messages"][name] = buffers.refused_count
        result["din4150_3_guideline_points"] = len(self.guidelines.frequency_hz)
        return result


class MonitorWindow:
    """The figure: built on the GUI thread, redrawn from a GUI timer from copies of the buffers."""

    def __init__(self, monitor, options):
        import matplotlib.pyplot as plt

        self.plt = plt
        self.monitor = monitor
        self.options = options
        self.start_wall_s = time.monotonic()
        self.exit_requested = False
        self.screenshot_done = False
        self.rows = {}  # name -> artists of its row
        self.row_names = []
        self.last_canvas_size = None
        self.figure = plt.figure(figsize=(14.0, 3.0), dpi=100)
        self.figure.canvas.mpl_connect("close_event", lambda event: self.request_exit())
        try:
            # Top left of the screen: test_monitor.py finds the axes of a screen grab where the layout says.
            self.figure.canvas.manager.window.wm_geometry("+0+0")
        except AttributeError:  # a backend without a Tk window
            pass
        self.build_layout([])
        self.timer = self.figure.canvas.new_timer(interval=int(1000.0 / options.redraw_hz))
        self.timer.add_callback(self.tick)
        self.timer.start()

    def request_exit(self):
        self.exit_requested = True

    # ------------------------------------------------------------------ layout
    def build_layout(self, sensor_names):
        from matplotlib.gridspec import GridSpec
        from matplotlib.lines import Line2D
        from matplotlib.transforms import blended_transform_factory

        figure = self.figure
        figure.clf()
        self.rows = {}
        self.row_names = list(sensor_names)
        rows = max(1, len(sensor_names))
        height_in = min(1.3 + 2.3 * rows, 10.0)
        figure.set_size_inches(14.0, height_in, forward=True)
        # Fixed margins (in inches) rather than a layout engine: axes stay put while titles change.
        self.title = figure.suptitle("", x=0.01, y=1.0 - 0.12 / height_in, ha="left", va="top", fontsize=11)
        if not sensor_names:
            self.waiting_text = figure.text(0.5, 0.5, "", ha="center", va="center", fontsize=14)
            self.print_layout()
            return
        self.waiting_text = None
        figure.legend([Line2D([], [], color=c, lw=1.5) for c in COMPONENT_COLOURS],
                      [f"velocity {c}" for c in COMPONENT_NAMES], loc="upper right", ncol=3, fontsize=8,
                      bbox_to_anchor=(0.99, 1.0 - 0.02 / height_in), frameon=False)
        grid = GridSpec(rows, 4, figure=figure, width_ratios=[3.0, 1.5, 1.5, 2.0], left=0.055, right=0.99,
                        top=1.0 - 0.95 / height_in, bottom=0.45 / height_in, hspace=0.45, wspace=0.28)
        for row, name in enumerate(sensor_names):
            artists = {}
            velocity_axes = figure.add_subplot(grid[row, 0])
            artists["velocity_lines"] = [velocity_axes.plot([], [], color=colour, lw=1.2)[0]
                                         for colour in COMPONENT_COLOURS]
            velocity_axes.set_ylabel("mm/s", fontsize=8)
            artists["velocity_title"] = velocity_axes.set_title(name, loc="left", fontsize=9, fontweight="bold")
            kb_f_axes = figure.add_subplot(grid[row, 1])
            kb_f_axes.set_yscale("log")
            artists["kb_f_line"] = kb_f_axes.plot([], [], color=KB_F_COLOUR, lw=1.4)[0]
            artists["a_u_line"] = kb_f_axes.axhline(1.0, color=A_U_COLOUR, lw=1.0, ls="--", visible=False)
            artists["a_o_line"] = kb_f_axes.axhline(1.0, color=A_O_COLOUR, lw=1.0, ls="--", visible=False)
            # The guide value labels sit on their lines: x in axes fraction, y in KB_F.
            on_line = blended_transform_factory(kb_f_axes.transAxes, kb_f_axes.transData)
            artists["a_u_text"] = kb_f_axes.text(0.99, 1.0, "", transform=on_line, ha="right", va="bottom",
                                                 fontsize=7, color=A_U_COLOUR)
            artists["a_o_text"] = kb_f_axes.text(0.99, 1.0, "", transform=on_line, ha="right", va="bottom",
                                                 fontsize=7, color=A_O_COLOUR)
            artists["kb_f_text"] = kb_f_axes.text(0.02, 0.03, "", transform=kb_f_axes.transAxes, va="bottom",
                                                  fontsize=7, color=A_O_COLOUR)
            artists["kb_f_title"] = kb_f_axes.set_title("KB_F(t), DIN 4150-2", loc="left", fontsize=8)
            ppv_axes = figure.add_subplot(grid[row, 2])
            # The sensor's kind is known from its first metrics message: drawn again then (ppv_kind).
            railvib_plots.din4150_3_axes(ppv_axes, self.monitor.guidelines)
            artists["ppv_kind"] = None
            artists["ppv_marker"] = railvib_plots.mark_ppv(ppv_axes, float("nan"), float("nan"), 2)
            artists["ppv_text"] = ppv_axes.text(0.02, 0.97, "", transform=ppv_axes.transAxes, va="top", fontsize=7)
            octave_axes = figure.add_subplot(grid[row, 3])
            railvib_plots.third_octave_axes(octave_axes)
            artists["bars"] = None
            artists["bar_centres_hz"] = None
            for axes in (velocity_axes, kb_f_axes, ppv_axes, octave_axes):
                axes.tick_params(labelsize=7)
                axes.grid(True, lw=0.3, alpha=0.5)
            if row == rows - 1:
                velocity_axes.set_xlabel("simulation time (s)", fontsize=8)
                kb_f_axes.set_xlabel("simulation time (s)", fontsize=8)
            else:
                ppv_axes.set_xlabel("")
                octave_axes.set_xlabel("")
            artists["axes"] = {"velocity": velocity_axes, "kb_f": kb_f_axes, "ppv": ppv_axes,
                               "third_octave": octave_axes}
            self.rows[name] = artists
        self.print_layout()

    def print_layout(self):
        """Every axes' box in canvas pixels (left, top, right, bottom; origin top left), for tests."""
        width_px, height_px = self.figure.canvas.get_width_height()
        self.last_canvas_size = (width_px, height_px)
        layout = {"canvas": [width_px, height_px]}
        for name, artists in self.rows.items():
            for kind, axes in artists["axes"].items():
                box = axes.get_window_extent()
                layout.setdefault(kind, {})[name] = [round(box.x0), round(height_px - box.y1), round(box.x1),
                                                     round(height_px - box.y0)]
        with _log_lock:
            print(LAYOUT_PREFIX + json.dumps(layout), flush=True)

    # ------------------------------------------------------------------ redraw
    def tick(self):
        elapsed_s = time.monotonic() - self.start_wall_s
        if self.exit_requested or (self.options.exit_after is not None and elapsed_s >= self.options.exit_after):
            self.timer.stop()
            self.plt.close(self.figure)
            return
        with self.monitor.sensors_lock:
            sensor_names = list(self.monitor.sensors)
        if sensor_names != self.row_names:
            self.build_layout(sensor_names)
        elif self.figure.canvas.get_width_height() != self.last_canvas_size:
            self.print_layout()  # the window was resized
        self.update()
        if self.options.screenshot and not self.screenshot_done and elapsed_s >= self.options.screenshot_after:
            self.figure.savefig(self.options.screenshot, dpi=self.figure.dpi)
            self.screenshot_done = True
            log(f"figure saved to {self.options.screenshot}")
        self.figure.canvas.draw_idle()

    def update(self):
        import numpy as np

        if not self.row_names:
            self.title.set_text("railvib monitor: " + (self.monitor.status or "waiting"))
            self.waiting_text.set_text(self.monitor.status or "waiting")
            self.set_window_title(self.title.get_text())
            return
        now_s = 0.0
        total_samples = total_metrics = 0
        verdicts = []
        for name in self.row_names:
            buffers = self.monitor.sensors[name]
            with buffers.lock:
                velocity = np.array(buffers.velocity, dtype=float).reshape(-1, 4)
                kb_f = np.array(buffers.kb_f, dtype=float).reshape(-1, 2)
                metrics = buffers.latest_metrics
                total_samples += buffers.velocity_count
                total_metrics += buffers.metrics_count
                if buffers.last_velocity_t_s is not None:
                    now_s = max(now_s, buffers.last_velocity_t_s)
            self.update_row(name, velocity, kb_f, metrics)
            verdict = railvib_verdicts.verdict_name(metrics.verdict) if metrics else "no metrics yet"
            verdicts.append(f"{name}: {verdict}")
        for name in self.row_names:  # one time axis for every row: the newest sample of any sensor
            t_end = max(now_s, self.monitor.window_s)
            for kind in ("velocity", "kb_f"):
                self.rows[name]["axes"][kind].set_xlim(t_end - self.monitor.window_s, t_end)
        status = f"   [{self.monitor.status}]" if self.monitor.status else ""
        summary = (f"railvib monitor   t = {now_s:.3f} s (simulation)   {total_samples} velocity samples, "
                   f"{total_metrics} metrics received")
        # Two lines in the figure (the verdicts of many sensors do not fit beside the rest), one in the title bar.
        self.title.set_text(summary + status + "\n" + "   ".join(verdicts))
        self.set_window_title(summary + "   |   " + "   ".join(verdicts) + status)

    def set_window_title(self, text):
        manager = self.figure.canvas.manager
        if manager is not None:
            manager.set_window_title(text)

    def update_row(self, name, velocity, kb_f, metrics):
        import numpy as np

        artists = self.rows[name]
        axes = artists["axes"]
        for component, line in enumerate(artists["velocity_lines"]):
            line.set_data(velocity[:, 0], velocity[:, component + 1])
        peak_mm_s = float(np.max(np.abs(velocity[:, 1:]))) if len(velocity) else 0.0
        # Symmetric limits around zero, never narrower than 1 um/s (a silent sensor shows a flat line).
        half_span = max(1.1 * peak_mm_s, 1e-3)
        axes["velocity"].set_ylim(-half_span, half_span)

        a_u = getattr(metrics, "din4150_2_a_u", None) if metrics else None
        a_o = getattr(metrics, "din4150_2_a_o", None) if metrics else None
        artists["kb_f_line"].set_data(kb_f[:, 0], kb_f[:, 1])
        positive = kb_f[:, 1][kb_f[:, 1] > 0.0] if len(kb_f) else np.array([])
        top = max([2.0 * v for v in (a_o, a_u) if v] + [2.0 * float(positive.max()) if len(positive) else 1.0])
        bottom = min(1e-2, 0.5 * float(positive.min())) if len(positive) else 1e-2
        axes["kb_f"].set_ylim(max(bottom, 1e-6), top)
        for line, text, label, value in ((artists["a_u_line"], artists["a_u_text"], "A_u", a_u),
                                         (artists["a_o_line"], artists["a_o_text"], "A_o", a_o)):
            shown = bool(value and value > 0.0)
            line.set_visible(shown)
            text.set_visible(shown)
            if shown:
                line.set_ydata([value, value])
                text.set_y(value)
                text.set_text(f"{label} {value:g}")

        if metrics is None:
            artists["velocity_title"].set_text(f"{name}: waiting for metrics")
            artists["velocity_title"].set_color(VERDICT_COLOURS[None])
            artists["kb_f_title"].set_text("KB_F(t), DIN 4150-2")
            return
        verdict_2 = railvib_verdicts.verdict_name(metrics.din4150_2_verdict)
        verdict_3 = railvib_verdicts.verdict_name(metrics.din4150_3_verdict)
        artists["velocity_title"].set_text(f"{name}: {railvib_verdicts.verdict_name(metrics.verdict)}   "
                                           f"(DIN 4150-2 {verdict_2}, DIN 4150-3 {verdict_3})")
        artists["velocity_title"].set_color(VERDICT_COLOURS.get(metrics.verdict, VERDICT_COLOURS[None]))
        artists["kb_f_title"].set_text(f"KB_F {metrics.kb_f:.3g} (max {metrics.kb_f_max:.3g}), DIN 4150-2")
        # Messages of a build older than the A_u / A_o fields: say why the lines are missing.
        artists["kb_f_text"].set_text("" if a_u is not None and a_o is not None
                                      else "A_u / A_o not in the messages (rebuild railvib)")

        kind = railvib_verdicts.kind_name(metrics.kind)
        if artists["ppv_kind"] != kind:
            # The guideline that applies where the sensor stands (free field: none, drawn grey).
            ppv_axes = axes["ppv"]
            for line in list(ppv_axes.lines):
                if line is not artists["ppv_marker"]:
                    line.remove()
            for text in list(ppv_axes.texts):
                if text is not artists["ppv_text"]:
                    text.remove()
            railvib_plots.din4150_3_axes(ppv_axes, self.monitor.guidelines, kind=kind)
            if name != self.row_names[-1]:
                ppv_axes.set_xlabel("")
            artists["ppv_kind"] = kind
        component = metrics.governing_component if metrics.governing_component < 3 else 2
        governing_mm_s = metrics.governing_ppv_m_s * 1e3
        if governing_mm_s > 0.0:
            artists["ppv_marker"].set_data([metrics.dominant_frequency_hz], [governing_mm_s])
            artists["ppv_marker"].set_color(COMPONENT_COLOURS[component])
            artists["ppv_marker"].set_markeredgecolor("black")
        else:
            artists["ppv_marker"].set_data([], [])
        artists["ppv_text"].set_text(f"{COMPONENT_NAMES[component]}: {governing_mm_s:.3g} mm/s at "
                                     f"{metrics.dominant_frequency_hz:.1f} Hz\nlimit "
                                     f"{metrics.din4150_3_limit_m_s * 1e3:.3g} mm/s, PPV {metrics.ppv_m_s * 1e3:.3g}")
        self.update_bars(artists, list(metrics.third_octave_center_hz), list(metrics.third_octave_level_db))

    def update_bars(self, artists, centres_hz, levels_db):
        import numpy as np

        octave_axes = artists["axes"]["third_octave"]
        if not centres_hz or len(centres_hz) != len(levels_db):
            return
        bottom, top = railvib_plots.third_octave_floor(levels_db)
        if bottom is None:
            return
        levels = np.array(levels_db, dtype=float)
        levels = np.where(np.isfinite(levels), np.maximum(levels, bottom), bottom)
        if artists["bar_centres_hz"] != centres_hz:
            if artists["bars"] is not None:
                artists["bars"].remove()
            positions = np.arange(len(centres_hz))
            artists["bars"] = octave_axes.bar(positions, levels - bottom, bottom=bottom, width=0.8, color=BAR_COLOUR)
            artists["bar_centres_hz"] = centres_hz
            railvib_plots.third_octave_ticks(octave_axes, centres_hz, positions)
        for bar, level in zip(artists["bars"], levels):
            bar.set_y(bottom)
            bar.set_height(level - bottom)
        octave_axes.set_ylim(bottom, top)


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--window-s", type=float, default=5.0, help="sliding window of simulation time (s, default 5)")
    parser.add_argument("--sensors", help="comma-separated sensor names (default: discovered from the topics)")
    parser.add_argument("--screenshot", metavar="PNG", help="save the figure to PNG after --screenshot-after")
    parser.add_argument("--screenshot-after", type=float, default=5.0, metavar="S",
                        help="wall seconds after start for --screenshot (default 5)")
    parser.add_argument("--exit-after", type=float, metavar="S", help="exit after this many wall seconds")
    parser.add_argument("--redraw-hz", type=float, default=4.0, help="redraw rate (wall, default 4 Hz)")
    options = parser.parse_args(argv)
    if not options.window_s > 0.0:
        parser.error("--window-s must be > 0")
    if not options.redraw_hz > 0.0:
        parser.error("--redraw-hz must be > 0")
    options.sensors = [s for s in (options.sensors or "").split(",") if s.strip()] or None
    if options.sensors:
        options.sensors = [s.strip() for s in options.sensors]
    return options


def main(argv):
    options = parse_args(argv)
    import matplotlib

    matplotlib.use("TkAgg")
    monitor = Monitor(options)
    window = MonitorWindow(monitor, options)
    # Ctrl+C and SIGTERM end the monitor like closing the window (the timer sees the flag).
    for signal_number in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signal_number, lambda number, frame: window.request_exit())
    threading.Thread(target=monitor.ros_thread, name="ros", daemon=True).start()
    window.plt.show()
    monitor.stopping.set()
    print(json.dumps(monitor.counts()), flush=True)
    try:
        import rospy

        rospy.signal_shutdown("monitor closed")
    except Exception:  # rospy never started (no master)
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
