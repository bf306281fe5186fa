#!/usr/bin/env python3
"""Listens to what a replay gives its users and dumps it as JSON (every 0.25 s and at shutdown) (used by scenario_checks.py).

Records: every soil surface point cloud of the scene visualizer (stamp, grid size, the
vertical_velocity_mm_s field), the namespaces and frames of the site markers, the last
live metrics per virtual sensor, and the tram frames seen on /tf.

usage: replay_probe.py OUT.json   (ROS_MASTER_URI names the replay's master)
"""
import json
import os
import sys
import threading
import time

import rospy
from sensor_msgs import point_cloud2
from sensor_msgs.msg import PointCloud2
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import MarkerArray

from railvib.msg import VibrationMetrics


def main():
    out_path = sys.argv[1]
    rospy.init_node("replay_probe", anonymous=True)  # waits for the launch's master
    data = {"clouds": [], "marker_namespaces": [], "marker_frames": [], "metrics": {}, "tf_frames": {},
            "tf_messages": 0}
    lock = threading.Lock()  # the callbacks run on rospy's threads, the dump on its own

    def on_cloud(msg):
        values = [p[0] for p in point_cloud2.read_points(msg, field_names=["vertical_velocity_mm_s"])]
        with lock:
            data["clouds"].append({"stamp_ns": msg.header.stamp.to_nsec(), "width": msg.width, "height": msg.height,
                                   "values_mm_s": values})

    def on_site(msg):
        with lock:
            data["marker_namespaces"] = sorted({m.ns for m in msg.markers})
            data["marker_frames"] = sorted({m.header.frame_id for m in msg.markers})

    def on_metrics(msg):
        with lock:
            data["metrics"][msg.sensor_name] = {"kb_f_max": msg.kb_f_max, "ppv_m_s": msg.ppv_m_s}

    def on_tf(msg):
        with lock:
            data["tf_messages"] += 1
            for t in msg.transforms:
                data["tf_frames"][t.child_frame_id] = data["tf_frames"].get(t.child_frame_id, 0) + 1

    def dump():
        # Written whole and renamed, so a reader polling the file never sees half of it.
        with lock:
            text = json.dumps(data)
        tmp = out_path + ".tmp"
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, out_path)

    rospy.Subscriber("/visualization/surface_velocity", PointCloud2, on_cloud, queue_size=None)
    rospy.Subscriber("/visualization/site", MarkerArray, on_site, queue_size=10)
    rospy.Subscriber("/sensor_metrics", VibrationMetrics, on_metrics, queue_size=None)
    rospy.Subscriber("/tf", TFMessage, on_tf, queue_size=None)
    rospy.on_shutdown(dump)

    def dump_every_quarter_second():
        # Wall time, not rospy.Timer: under /use_sim_time a timer would stop with the replay's /clock.
        while not rospy.is_shutdown():
            time.sleep(0.25)
            dump()

    threading.Thread(target=dump_every_quarter_second, daemon=True).start()
    rospy.spin()


if __name__ == "__main__":
    main()
