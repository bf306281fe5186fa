#!/usr/bin/env python3
"""rostest check of a recorded railvib bag.

Waits for the recorder's latched status, then asserts for every stream topic:
blocks contiguous from sample 0 (first_sample_index), the last block flagged
end_of_stream, each block's bag time equal to its header stamp (simulation
time), and the sample count equal to duration / period + 1.

With ~tf_pose_period_s, also asserts that /tf holds every tram pose from t = 0
to the end (one message per period, bag time = the poses' stamp) and that
/tf_static holds the ~static_frames.

With ~check_metrics, also asserts that the live metrics of every virtual
sensor (last message of each sensor on /sensor_metrics) equal KB_Fmax and PPV
recomputed offline by `railvib_tool metrics` from the recorded sensor_samples.
"""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import rosbag
import rospy
import rostest
from std_msgs.msg import String

TIME_MIN_NS = 1  # rosbag's ros::TIME_MIN: stamps at t = 0 are stored at 1 ns


sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "scripts"))
from railvib_paths import find_railvib_tool  # noqa: E402


class StreamBagTest(unittest.TestCase):
    def setUp(self):
        rospy.init_node("check_stream_bag", anonymous=True)
        self.bag_path = rospy.get_param("~bag")
        self.streams = rospy.get_param("~streams")
        self.duration_s = float(rospy.get_param("~expected_duration_s"))
        self.check_metrics = rospy.get_param("~check_metrics", False)
        self.status = None
        rospy.Subscriber(rospy.get_param("~recorder_status"), String, self._on_status)

    def _on_status(self, msg):
        self.status = msg.data

    def wait_for_recorder(self):
        deadline = time.time() + float(rospy.get_param("~wait_s", 360.0))
        while self.status is None and time.time() < deadline and not rospy.is_shutdown():
            time.sleep(0.1)
        self.assertIsNotNone(self.status, "recorder did not report within the time limit")
        self.assertTrue(self.status.startswith("closed"), "recorder status: " + self.status)

    def test_bag_streams_complete(self):
        self.wait_for_recorder()
        with rosbag.Bag(self.bag_path) as bag:
            for topic in self.streams:
                blocks = [(m, t) for _, m, t in bag.read_messages(topics=[topic])]
                self.assertGreater(len(blocks), 0, topic + ": no block recorded")
                blocks.sort(key=lambda mt: mt[0].first_sample_index)
                expected_index = 0
                for msg, t in blocks:
                    self.assertEqual(msg.first_sample_index, expected_index, topic + ": gap or duplicate")
                    expected_index += msg.sample_count
                    stamp_ns = max(msg.header.stamp.to_nsec(), TIME_MIN_NS)
                    self.assertEqual(t.to_nsec(), stamp_ns, topic + ": bag time differs from header stamp")
                    period = msg.sample_period_s
                    self.assertAlmostEqual(msg.header.stamp.to_sec(), msg.first_sample_index * period, delta=1e-6)
                self.assertTrue(blocks[-1][0].end_of_stream, topic + ": last block not flagged end_of_stream")
                self.assertTrue(all(not m.end_of_stream for m, _ in blocks[:-1]), topic + ": early end_of_stream")
                expected_samples = int(round(self.duration_s / blocks[0][0].sample_period_s)) + 1
                self.assertEqual(expected_index, expected_samples, topic + ": sample count")

        if self.check_metrics:
            self.check_live_metrics_against_offline()
        if rospy.has_param("~tf_pose_period_s"):
            self.check_tf_recorded(float(rospy.get_param("~tf_pose_period_s")), rospy.get_param("~static_frames"))

    def check_tf_recorded(self, period_s, static_frames):
        with rosbag.Bag(self.bag_path) as bag:
            stamps = []
            for _, m, t in bag.read_messages(topics=["/tf"]):
                frames = {tr.child_frame_id for tr in m.transforms}
                self.assertIn("tram/front_carbody", frames)
                stamp = max(tr.header.stamp for tr in m.transforms)
                self.assertTrue(all(tr.header.stamp == stamp for tr in m.transforms), "one pose time per message")
                self.assertEqual(t.to_nsec(), max(stamp.to_nsec(), TIME_MIN_NS), "/tf: bag time differs from stamp")
                stamps.append(stamp.to_sec())
            expected = int(round(self.duration_s / period_s)) + 1
            self.assertEqual(len(stamps), expected, "/tf: tram pose count")
            for k, s in enumerate(sorted(stamps)):
                self.assertAlmostEqual(s, k * period_s, delta=1e-6, msg="/tf: pose times")
            recorded_static = set()
            for _, m, _ in bag.read_messages(topics=["/tf_static"]):
                recorded_static |= {tr.child_frame_id for tr in m.transforms}
            for frame in static_frames:
                self.assertIn(frame, recorded_static, "/tf_static")

    def check_live_metrics_against_offline(self):
        with rosbag.Bag(self.bag_path) as bag:
            blocks = sorted((m for _, m, _ in bag.read_messages(topics=["/sensor_samples"])),
                            key=lambda m: m.first_sample_index)
            self.assertGreater(len(blocks), 0, "no sensor_samples recorded")
            names = list(blocks[0].sensor_names)
            period = blocks[0].sample_period_s
            live = {}
            for _, m, _ in bag.read_messages(topics=["/sensor_metrics"]):
                live[m.sensor_name] = m  # the last one is the whole record
        tool = find_railvib_tool()
        self.assertIsNotNone(tool, "railvib_tool not found")
        workdir = tempfile.mkdtemp(prefix="railvib_metrics_")
        for i, name in enumerate(names):
            self.assertIn(name, live, name + ": no live metrics recorded")
            path = os.path.join(workdir, name + ".csv")
            with open(path, "w", newline="") as f:
                w = csv.writer(f, lineterminator="\n")
                w.writerow(["t_s", "vx", "vy", "vz"])
                k = 0
                for b in blocks:
                    for s in range(b.sample_count):
                        base = (s * len(names) + i) * 3
                        w.writerow([repr(k * period)] + [repr(x) for x in b.velocity_m_s[base:base + 3]])
                        k += 1
            # Own session: roslaunch's SIGINT to the launch when the recorder ends must not reach it.
            out = subprocess.run([tool, "metrics", "--csv", path, "--column", "vx,vy,vz"], capture_output=True,
                                 text=True, start_new_session=True)
            self.assertEqual(out.returncode, 0, out.stderr)
            offline = json.loads(out.stdout)
            kb = offline["din4150_2"]["kb_fmax"]
            ppv = offline["din4150_3"]["vector_peak_mm_s"] * 1e-3
            # Same core code on the same samples: equal to rounding of the CSV round trip.
            self.assertAlmostEqual(live[name].kb_f_max, kb, delta=1e-9 + 1e-6 * abs(kb), msg=name + " KB_Fmax")
            self.assertAlmostEqual(live[name].ppv_m_s, ppv, delta=1e-12 + 1e-6 * abs(ppv), msg=name + " PPV")
            # The governing component and the DIN 4150-3 verdict: one rule (signal::din4150_3Verdict) for both.
            self.assertEqual(["vx", "vy", "vz"][live[name].governing_component],
                             offline["din4150_3"]["governing_component"], name + " governing component")
            self.assertEqual(live[name].din4150_3_verdict == 0, offline["din4150_3"]["verdict"] == "met",
                             name + " DIN 4150-3 verdict")
        shutil.rmtree(workdir, ignore_errors=True)


if __name__ == "__main__":
    rostest.rosrun("railvib", "check_stream_bag", StreamBagTest, sys.argv)
