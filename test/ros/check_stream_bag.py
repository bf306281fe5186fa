#!/usr/bin/env python3
"""rostest check of a recorded railvib bag.

Waits for the recorder's latched status, then asserts for every stream topic:
blocks contiguous from sample 0 (first_sample_index), the last block flagged
end_of_stream, each block's bag time equal to its header stamp (simulation
time), and the sample count equal to duration / period + 1.
"""
import sys
import time
import unittest

import rosbag
import rospy
import rostest
from std_msgs.msg import String

TIME_MIN_NS = 1  # rosbag's ros::TIME_MIN: stamps at t = 0 are stored at 1 ns


class StreamBagTest(unittest.TestCase):
    def setUp(self):
        rospy.init_node("check_stream_bag", anonymous=True)
        self.bag_path = rospy.get_param("~bag")
        self.streams = rospy.get_param("~streams")
        self.duration_s = float(rospy.get_param("~expected_duration_s"))
        self.status = None
        rospy.Subscriber(rospy.get_param("~recorder_status"), String, self._on_status)

    def _on_status(self, msg):
        self.status = msg.data

    def test_bag_streams_complete(self):
        deadline = time.time() + 360.0
        while self.status is None and time.time() < deadline and not rospy.is_shutdown():
            time.sleep(0.1)
        self.assertIsNotNone(self.status, "recorder did not report within the time limit")
        self.assertTrue(self.status.startswith("closed"), "recorder status: " + self.status)
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


if __name__ == "__main__":
    rostest.rosrun("railvib", "check_stream_bag", StreamBagTest, sys.argv)
