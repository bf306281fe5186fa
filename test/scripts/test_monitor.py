#!/usr/bin/env python3
"""Test of the live vibration monitor (scripts/monitor.py), run by CTest in the workspace environment.

It starts a ROS master of its own (`roscore -p PORT`, a free port) and a virtual X display of its
own (`Xvfb :N`, a free display), runs the monitor on them without --sensors (so it must discover the
sensors from the topics), and publishes, like the virtual sensor node, two sensors' velocity
(20 Hz sine, 1 mm/s per component, 1 kHz) and VibrationMetrics (10 Hz): a short first pass, then
simulation time back to 0 and a second pass of 2 s, as a looping replay does. Then it grabs the real
screen with `xwd -root` and stops the monitor, which prints its counts as JSON. It checks:
- every velocity sample and metrics message published arrived, for each sensor, and no other sensor;
- the jump back in simulation time started a new pass and cleared the first pass's samples;
- the screen grab is not blank, and the three velocity colours are drawn inside each sensor's
  velocity axes (where the monitor's printed layout says they are);
- the monitor's own PNG (--screenshot) is the figure's canvas;
- the DIN 4150-3 guideline curve came from the core (railvib_tool din-guides);
- a foreign publisher's messages on the sensors' topics (KB_F NaN, another sensor's name, a verdict
  code out of range, a NaN velocity) are refused, counted apart, and not shown.
Every process it starts (roscore, Xvfb, the monitor) is stopped, also when a step fails.

usage: test_monitor.py [JUNIT_XML]
"""
import json
import math
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "scripts"
sys.path.insert(0, str(SCRIPTS))
import monitor  # noqa: E402  (its colours and layout line; importing it starts nothing)
import railvib_names as names  # noqa: E402
import railvib_process  # noqa: E402
from rviz_screenshot import xwd_to_rgb  # noqa: E402
sys.path.insert(0, str(ROOT / "test" / "ros"))
from junit_xml import run_verbose, write_junit  # noqa: E402

import matplotlib.image  # noqa: E402  (rviz_screenshot has chosen the Agg backend)

SENSORS = ("ground_a", "house_b")
SAMPLE_RATE_HZ = 1000.0
METRICS_EVERY = 100  # samples per metrics message: 10 Hz, as the virtual sensor node
FIRST_PASS_SAMPLES = 500  # 0.5 s, then simulation time goes back to 0
SECOND_PASS_SAMPLES = 2000  # 2 s: what the window shows at the grab
SINE_HZ = 20.0
AMPLITUDE_M_S = 1e-3
WINDOW_S = 2.5  # the monitor's --window-s: the second pass fills most of the velocity axes
SCREEN = (1600, 1000)
CANVAS_SCREENSHOT_AFTER_S = 12.0
EXIT_AFTER_S = 50.0  # a backstop only: the test stops the monitor with SIGINT
# A pixel counts as a line colour when every channel is within this of it (anti-aliasing blends the
# line's edges with the white background).
COLOUR_TOLERANCE = 40
MIN_LINE_PIXELS = 1000  # per component colour, per sensor's velocity axes (about 4 000-16 000 drawn)

WORK = pathlib.Path(tempfile.mkdtemp(prefix="railvib_monitor_test_"))


def free_display():
    """A display number with neither a lock file nor a socket (another X server's)."""
    for n in range(100 + os.getpid() % 300, 500):
        if not os.path.exists(f"/tmp/.X{n}-lock") and not os.path.exists(f"/tmp/.X11-unix/X{n}"):
            return n
    raise RuntimeError("no free X display number in 100..499")


def core_services_up(uri):
    import rosgraph

    try:
        rosgraph.Master("/monitor_test", master_uri=uri).lookupNode("/rosout")
        return True
    except Exception:  # master not up, or /rosout not registered yet
        return False


def stop(process, timeout_s=10.0):
    """Ends a process the test started and its children (each runs in a session of its own)."""
    if process is not None:
        railvib_process.stop(process, grace_s=timeout_s, term_grace_s=5.0)


def sine_m_s(t_s, component):
    # The components 120 degrees apart, so that each colour is visible beside the others.
    return AMPLITUDE_M_S * math.sin(2.0 * math.pi * SINE_HZ * t_s + component * 2.0 * math.pi / 3.0)


class Monitor(unittest.TestCase):
    """One monitor run (setUpClass) and checks of what it received and drew."""

    processes = []
    published = {"velocity": {}, "metrics": {}}
    foreign_published = {}
    counts = None
    layout = None
    grab = None
    monitor_stdout = ""
    monitor_stderr = ""

    @classmethod
    def setUpClass(cls):
        # ctest's timeout and Ctrl+C end the test through SystemExit/KeyboardInterrupt: cleaned up below.
        signal.signal(signal.SIGTERM, lambda number, frame: sys.exit(128 + number))
        try:
            cls.run_monitor()
        except BaseException:
            cls.stop_all()
            raise
        cls.stop_all()

    @classmethod
    def tearDownClass(cls):
        cls.stop_all()

    @classmethod
    def stop_all(cls):
        for process in reversed(cls.processes):
            stop(process)

    @classmethod
    def start(cls, args, env, log_name):
        out = open(WORK / (log_name + ".out"), "w")
        err = open(WORK / (log_name + ".err"), "w")
        process = subprocess.Popen(args, env=env, stdout=out, stderr=err, start_new_session=True)
        cls.processes.append(process)
        return process

    @classmethod
    def run_monitor(cls):
        port = railvib_process.free_port()
        display = free_display()
        uri = f"http://127.0.0.1:{port}"
        # The test's own node and every child use this master, on loopback; logs stay in WORK.
        os.environ.update(ROS_MASTER_URI=uri, ROS_IP="127.0.0.1", ROS_LOG_DIR=str(WORK / "ros_log"))
        os.environ.pop("ROS_HOSTNAME", None)
        env = dict(os.environ, DISPLAY=f":{display}")
        # The master with ROS's own core services: the monitor needs no railvib rosout, and the test
        # must not depend on that node being built.
        core_env = dict(env, ROS_ETC_DIR="/etc/ros") if os.path.isfile("/etc/ros/roscore.xml") else env
        roscore = cls.start(["roscore", "-p", str(port)], core_env, "roscore")
        xvfb = cls.start(["Xvfb", f":{display}", "-screen", "0", f"{SCREEN[0]}x{SCREEN[1]}x24", "-nolisten", "tcp"],
                         env, "xvfb")

        deadline = time.monotonic() + 20.0
        while True:
            if roscore.poll() is not None:
                raise RuntimeError(f"roscore exited ({roscore.returncode}): {(WORK / 'roscore.err').read_text()}")
            if xvfb.poll() is not None:
                raise RuntimeError(f"Xvfb exited ({xvfb.returncode}): {(WORK / 'xvfb.err').read_text()}")
            # roscore is up once its /rosout runs (a master alone may still be shut down by a failed core).
            if core_services_up(uri) and os.path.exists(f"/tmp/.X11-unix/X{display}"):
                break
            if time.monotonic() > deadline:
                raise RuntimeError("roscore or Xvfb did not come up within 20 s")
            time.sleep(0.2)

        canvas_png = WORK / "canvas.png"
        monitor_process = cls.start([sys.executable, str(SCRIPTS / "monitor.py"), "--window-s", str(WINDOW_S),
                                     "--screenshot", str(canvas_png), "--screenshot-after",
                                     str(CANVAS_SCREENSHOT_AFTER_S), "--exit-after", str(EXIT_AFTER_S)],
                                    env, "monitor")
        monitor_started = time.monotonic()

        import rospy
        from geometry_msgs.msg import Vector3Stamped
        import railvib.msg as rm

        # rospy.init_node waits for ever for a master that is gone: bound it.
        starter = threading.Thread(target=rospy.init_node, args=("monitor_test_publisher",),
                                   kwargs={"anonymous": True, "disable_signals": True}, daemon=True)
        starter.start()
        starter.join(timeout=20.0)
        if starter.is_alive() or roscore.poll() is not None:
            raise RuntimeError("the test's ROS node could not start (master gone?): "
                               + (WORK / "roscore.err").read_text()[-2000:])
        # Queues larger than everything published: rospy's publisher drops nothing then.
        queue = FIRST_PASS_SAMPLES + SECOND_PASS_SAMPLES + 10
        publishers = {name: (rospy.Publisher(names.sensor_topic(name, "velocity"), Vector3Stamped, queue_size=queue),
                             rospy.Publisher(names.sensor_topic(name, "metrics"), rm.VibrationMetrics,
                                             queue_size=queue))
                      for name in SENSORS}
        # The monitor finds the topics itself; wait until it is connected to every one.
        deadline = time.monotonic() + 30.0
        while not all(p.get_num_connections() > 0 for pair in publishers.values() for p in pair):
            if monitor_process.poll() is not None:
                raise RuntimeError(f"the monitor exited ({monitor_process.returncode}) before subscribing: "
                                   + (WORK / "monitor.err").read_text()[-2000:])
            if time.monotonic() > deadline:
                raise RuntimeError("the monitor did not subscribe to every sensor topic within 30 s")
            time.sleep(0.1)

        for name in SENSORS:
            cls.published["velocity"][name] = 0
            cls.published["metrics"][name] = 0
        for pass_samples in (FIRST_PASS_SAMPLES, SECOND_PASS_SAMPLES):
            cls.publish_pass(publishers, pass_samples, rm)
        cls.publish_foreign(publishers, rm)
        publish_done = time.monotonic()

        # A few redraws at 4 Hz after the last sample, then the real screen.
        time.sleep(2.0)
        dump = subprocess.run(["xwd", "-root", "-silent", "-display", f":{display}"], capture_output=True,
                              check=True, timeout=30).stdout
        cls.grab = xwd_to_rgb(dump)
        matplotlib.image.imsave(WORK / "grab.png", cls.grab)
        cls.layout = cls.read_layout()
        # The monitor's own PNG comes at CANVAS_SCREENSHOT_AFTER_S after its start.
        while not canvas_png.exists() and time.monotonic() < monitor_started + CANVAS_SCREENSHOT_AFTER_S + 10.0:
            time.sleep(0.2)
        cls.canvas_png = canvas_png
        cls.canvas_after_data = monitor_started + CANVAS_SCREENSHOT_AFTER_S > publish_done + 1.0
        stop(monitor_process, timeout_s=15.0)
        rospy.signal_shutdown("test done")
        cls.monitor_stdout = (WORK / "monitor.out").read_text()
        cls.monitor_stderr = (WORK / "monitor.err").read_text()
        json_lines = [line for line in cls.monitor_stdout.splitlines() if line.startswith("{")]
        if monitor_process.returncode != 0 or not json_lines:
            raise RuntimeError(f"the monitor ended with {monitor_process.returncode} and no JSON line:\n"
                               f"{cls.monitor_stdout[-2000:]}\n{cls.monitor_stderr[-2000:]}")
        cls.counts = json.loads(json_lines[-1])

    @classmethod
    def publish_pass(cls, publishers, sample_count, rm):
        """One pass from simulation time 0, paced at about real time (10 samples per 10 ms)."""
        import rospy
        from geometry_msgs.msg import Vector3Stamped

        start = time.monotonic()
        for k in range(sample_count):
            t_s = k / SAMPLE_RATE_HZ
            for index, (name, (velocity_publisher, metrics_publisher)) in enumerate(publishers.items()):
                v = Vector3Stamped()
                v.header.stamp = rospy.Time.from_sec(t_s)
                v.header.frame_id = names.sensor_frame(name)
                v.vector.x, v.vector.y, v.vector.z = (sine_m_s(t_s, c) for c in range(3))
                velocity_publisher.publish(v)
                cls.published["velocity"][name] += 1
                if (k + 1) % METRICS_EVERY == 0:
                    metrics_publisher.publish(cls.metrics_message(rm, name, index, t_s, k + 1))
                    cls.published["metrics"][name] += 1
            if k % 10 == 9:
                time.sleep(max(0.0, start + (k + 1) / SAMPLE_RATE_HZ - time.monotonic()))

    @classmethod
    def publish_foreign(cls, publishers, rm):
        """What a foreign publisher might send on each sensor's topics, at the last time of the pass:
        a metrics message with KB_F NaN, one naming another sensor, one with a verdict code 9, and a
        velocity with x NaN. None may be shown or counted as received."""
        import rospy
        from geometry_msgs.msg import Vector3Stamped

        t_s = (SECOND_PASS_SAMPLES - 1) / SAMPLE_RATE_HZ
        for index, (name, (velocity_publisher, metrics_publisher)) in enumerate(publishers.items()):
            bad = [cls.metrics_message(rm, name, index, t_s, SECOND_PASS_SAMPLES) for _ in range(3)]
            bad[0].kb_f = math.nan
            bad[1].sensor_name = "not_" + name
            bad[2].verdict = 9
            for m in bad:
                metrics_publisher.publish(m)
            v = Vector3Stamped()
            v.header.stamp = rospy.Time.from_sec(t_s)
            v.vector.x = math.nan
            velocity_publisher.publish(v)
            cls.foreign_published[name] = len(bad) + 1

    @staticmethod
    def metrics_message(rm, name, index, t_s, samples):
        import rospy

        m = rm.VibrationMetrics()
        m.header.stamp = rospy.Time.from_sec(t_s)
        m.header.frame_id = names.sensor_frame(name)
        m.sensor_name = name
        m.kb_f = 0.05 * (1 + index) * min(1.0, samples / 500.0)
        m.kb_f_max = m.kb_f
        m.ppv_m_s = AMPLITUDE_M_S * math.sqrt(1.5)
        m.ppv_vertical_m_s = AMPLITUDE_M_S
        m.governing_component = 2
        m.governing_ppv_m_s = AMPLITUDE_M_S
        m.dominant_frequency_hz = SINE_HZ
        m.din4150_3_limit_m_s = 7.5e-3
        m.third_octave_center_hz = [1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0, 10.0, 12.5, 16.0, 20.0,
                                    25.0, 31.5, 40.0, 50.0, 63.0, 80.0]
        rms_db = 20.0 * math.log10(AMPLITUDE_M_S / math.sqrt(2.0) / 1e-9)
        m.third_octave_level_db = [rms_db - 3.0 * abs(i - 13) for i in range(len(m.third_octave_center_hz))]
        m.din4150_2_verdict = index  # OK, then WARN: two verdict colours
        m.din4150_3_verdict = 0
        m.verdict = index
        m.din4150_2_a_u = 0.15
        m.din4150_2_a_o = 3.0
        m.din4150_2_a_r = 0.07
        return m

    @classmethod
    def read_layout(cls):
        lines = [line for line in (WORK / "monitor.out").read_text().splitlines()
                 if line.startswith(monitor.LAYOUT_PREFIX)]
        if not lines:
            raise RuntimeError("the monitor printed no layout")
        return json.loads(lines[-1][len(monitor.LAYOUT_PREFIX):])

    # ------------------------------------------------------------------ checks
    def test_every_velocity_sample_arrived(self):
        self.assertEqual(self.counts["velocity_samples"], self.published["velocity"])
        self.assertEqual(set(self.counts["velocity_samples"]), set(SENSORS))  # found by discovery, no other

    def test_every_metrics_message_arrived(self):
        self.assertEqual(self.counts["metrics_messages"], self.published["metrics"])

    def test_foreign_messages_are_refused_not_shown(self):
        # Every one of them refused (and the valid streams above counted exactly, without them).
        self.assertEqual(self.counts["refused_messages"], self.foreign_published)
        self.assertIn("refused 1 message(s) so far", self.monitor_stdout + self.monitor_stderr)

    def test_a_jump_back_in_time_starts_a_new_pass(self):
        self.assertEqual(self.counts["passes"], {name: 2 for name in SENSORS})
        # Only the second pass is left (the first one's 500 samples were cleared).
        self.assertEqual(self.counts["window_velocity_samples"], {name: SECOND_PASS_SAMPLES for name in SENSORS})

    def test_the_screen_grab_is_not_blank(self):
        distinct = len(np.unique(self.grab.reshape(-1, 3), axis=0))
        self.assertGreater(distinct, 64, "the screen grab has almost no colours: no window drawn")

    def test_the_velocity_lines_are_in_the_velocity_axes(self):
        self.assertLessEqual(self.layout["canvas"][0], SCREEN[0])
        for name in SENSORS:
            left, top, right, bottom = self.layout["velocity"][name]
            area = self.grab[top:bottom, left:right].astype(int)
            self.assertGreater(area.size, 0, f"{name}: empty velocity axes {self.layout['velocity'][name]}")
            for component, colour in zip(monitor.COMPONENT_NAMES, monitor.COMPONENT_COLOURS):
                rgb = np.array([int(colour[i:i + 2], 16) for i in (1, 3, 5)])
                pixels = int(np.sum(np.all(np.abs(area - rgb) <= COLOUR_TOLERANCE, axis=2)))
                self.assertGreaterEqual(pixels, MIN_LINE_PIXELS,
                                        f"{name}: velocity {component} ({colour}) has {pixels} pixels in its axes "
                                        f"(grab: {WORK / 'grab.png'})")

    def test_the_monitor_saves_its_canvas(self):
        self.assertTrue(self.canvas_png.exists(), "--screenshot wrote no PNG")
        image = matplotlib.image.imread(self.canvas_png)
        self.assertEqual([image.shape[1], image.shape[0]], self.layout["canvas"])
        rgb = (image[:, :, :3] * 255).astype(np.uint8)
        self.assertGreater(len(np.unique(rgb.reshape(-1, 3), axis=0)), 64)
        if self.canvas_after_data:  # taken after the last sample: the velocity lines are on it too
            left, top, right, bottom = self.layout["velocity"][SENSORS[0]]
            area = rgb[top:bottom, left:right].astype(int)
            colour = monitor.COMPONENT_COLOURS[0]
            reference = np.array([int(colour[i:i + 2], 16) for i in (1, 3, 5)])
            self.assertGreaterEqual(int(np.sum(np.all(np.abs(area - reference) <= COLOUR_TOLERANCE, axis=2))),
                                    MIN_LINE_PIXELS)

    def test_the_din_4150_3_guideline_comes_from_the_core(self):
        self.assertGreater(self.counts["din4150_3_guideline_points"], 0,
                           "no DIN 4150-3 curve from railvib_tool din-guides: " + self.monitor_stderr[-1000:])


if __name__ == "__main__":
    started = time.monotonic()
    suite = unittest.defaultTestLoader.loadTestsFromTestCase(Monitor)
    result = run_verbose(suite)
    if len(sys.argv) > 1:
        write_junit(result, "monitor_tests", Monitor, sys.argv[1])
    print(f"test_monitor: {time.monotonic() - started:.1f} s; files in {WORK}" if not result.wasSuccessful()
          else f"test_monitor: {time.monotonic() - started:.1f} s")
    if result.wasSuccessful():
        shutil.rmtree(WORK, ignore_errors=True)
    sys.exit(0 if result.wasSuccessful() else 1)
