#!/usr/bin/env python3
"""Listens to what a replay gives its users and dumps it as JSON at shutdown (used by scenario_checks.py).

Records: every soil surface point cloud of the scene visualizer (stamp, grid size, the
vertical_velocity_mm_s field), the namespaces and frames of the site markers, the last
live metrics per virtual sensor, and the tram frames seen on /tf.

usage: replay_probe.py OUT.json   (ROS_MASTER_URI names the replay's master)
"""
import json
import sys

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

    def on_cloud(msg):
        values = [p[0] for p in point_cloud2.read_points(msg, field_names=["vertical_velocity_mm_s"])]
        data["clouds"].append({"stamp_ns": msg.header.stamp.to_nsec(), "width": msg.width, "height": msg.height,
                               "values_mm_s": values})

    def on_site(msg):
        data["marker_namespaces"] = sorted({m.ns for m in msg.markers})
        data["marker_frames"] = sorted({m.header.frame_id for m in msg.markers})

    def on_metrics(msg):
        data["metrics"][msg.sensor_name] = {"kb_f_max": msg.kb_f_max, "ppv_m_s": msg.ppv_m_s}

    def on_tf(msg):
        data["tf_messages"] += 1
        for t in msg.transforms:
            data["tf_frames"][t.child_frame_id] = data["tf_frames"].get(t.child_frame_id, 0) + 1

    def dump():
        with open(out_path, "w") as f:
            json.dump(data, f)

    rospy.Subscriber("/visualization/surface_velocity", PointCloud2, on_cloud, queue_size=None)
    rospy.Subscriber("/visualization/site", MarkerArray, on_site, queue_size=10)
    rospy.Subscriber("/sensor_metrics", VibrationMetrics, on_metrics, queue_size=None)
    rospy.Subscriber("/tf", TFMessage, on_tf, queue_size=None)
    rospy.on_shutdown(dump)
    rospy.spin()


if __name__ == "__main__":
    main()
