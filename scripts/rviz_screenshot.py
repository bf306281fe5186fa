#!/usr/bin/env python3
"""Screenshots of a real RViz window showing a replayed railvib bag.

Starts a virtual X display (Xvfb), runs `roslaunch railvib replay.launch
bag:=BAG rviz:=true rate:=RATE` on it, and grabs the whole screen with `xwd`
at the chosen simulated times (the replay's /clock tells where it is). Each
grab is written as PNG (numpy + matplotlib, no image library needed).

    ./railvib exec python3 scripts/rviz_screenshot.py BAG OUT.png [--at 1.45] [--rate 0.5]

With several --at times, OUT.png gets a _<time>s suffix per grab.
Needs the Debian packages rviz, xvfb and x11-apps (`./railvib setup --viz`).
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402

import railvib_process  # noqa: E402


def die(msg):
    print("rviz_screenshot: error: " + msg, file=sys.stderr)
    sys.exit(1)


def xwd_to_rgb(data):
    """Decode an xwd dump of a TrueColor screen (ZPixmap, 24/32 bits per pixel) into an HxWx3 uint8 array."""
    header = np.frombuffer(data[:100], dtype=">u4")
    (header_size, version, pixmap_format, _depth, width, height, _xoffset, byte_order, _unit, _bit_order, _pad,
     bits_per_pixel, bytes_per_line, _visual_class, red_mask, green_mask, blue_mask, _bits_rgb, _cmap_entries,
     ncolors) = (int(v) for v in header[:20])
    if version != 7 or pixmap_format != 2 or bits_per_pixel not in (24, 32):
        die(f"unsupported xwd dump (version {version}, format {pixmap_format}, {bits_per_pixel} bpp)")
    offset = header_size + 12 * ncolors
    bytes_pp = bits_per_pixel // 8
    rows = np.frombuffer(data[offset:offset + height * bytes_per_line], dtype=np.uint8).reshape(height,
                                                                                             bytes_per_line)
    pixels = rows[:, :width * bytes_pp].reshape(height, width, bytes_pp).astype(np.uint32)
    order = range(bytes_pp) if byte_order == 0 else reversed(range(bytes_pp))  # 0: LSB first
    value = np.zeros((height, width), dtype=np.uint32)
    for shift, k in enumerate(order):
        value |= pixels[:, :, k] << np.uint32(8 * shift)

    def channel(mask):
        low = (mask & -mask).bit_length() - 1
        return ((value & np.uint32(mask)) >> np.uint32(low)).astype(np.uint8)

    return np.dstack([channel(red_mask), channel(green_mask), channel(blue_mask)])


def main():
    railvib_process.interrupts_by_default()
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bag")
    ap.add_argument("out", help="PNG file")
    ap.add_argument("--at", type=float, action="append", help="simulated time of a grab (s); default 1.45")
    ap.add_argument("--rate", type=float, default=0.5, help="replay rate factor (default 0.5)")
    ap.add_argument("--size", default="1280x800", help="screen size WxH (default 1280x800)")
    ap.add_argument("--display", default=":97")
    ap.add_argument("--port", type=int, default=11397, help="ROS master port of its own (default 11397), so a "
                    "running scenario on the default master is left alone")
    ap.add_argument("--timeout", type=float, default=300.0, help="give up after this many wall seconds")
    args = ap.parse_args()
    times = sorted(args.at or [1.45])
    for exe in ("Xvfb", "xwd", "rviz", "roslaunch"):
        if not shutil.which(exe):
            die(f"{exe} not found (./railvib setup --viz installs rviz, xvfb and x11-apps)")
    if not os.path.isfile(args.bag):
        die(f"no bag {args.bag}")

    os.environ["ROS_MASTER_URI"] = f"http://localhost:{args.port}"
    import rospy
    from rosgraph_msgs.msg import Clock

    env = dict(os.environ, DISPLAY=args.display, LIBGL_ALWAYS_SOFTWARE="1")
    xvfb = subprocess.Popen(["Xvfb", args.display, "-screen", "0", args.size + "x24", "-nolisten", "tcp"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    log = tempfile.NamedTemporaryFile(prefix="rviz_screenshot_", suffix=".log", delete=False)
    launch = None
    try:
        time.sleep(1.0)
        launch = subprocess.Popen(["roslaunch", "-p", str(args.port), "railvib", "replay.launch", "bag:=" + os.path.abspath(args.bag),
                                   "rviz:=true", f"rate:={args.rate}", "start_delay_s:=5"], env=env, stdout=log, stderr=subprocess.STDOUT,
                                  start_new_session=True)
        # Wait for the master the launch starts, then follow the replay's /clock.
        deadline = time.time() + args.timeout
        while time.time() < deadline:
            try:
                rospy.init_node("rviz_screenshot", anonymous=True, disable_signals=True)
                break
            except Exception:  # master not up yet
                time.sleep(0.5)
        clock = {"t": -1.0}
        rospy.Subscriber("/clock", Clock, lambda m: clock.__setitem__("t", m.clock.to_sec()))
        for t in times:
            while clock["t"] < t:
                if time.time() > deadline or launch.poll() is not None:
                    die(f"replay ended or timed out before t = {t} s (log: {log.name})")
                time.sleep(0.005)
            grabbed_at = clock["t"]
            dump = subprocess.run(["xwd", "-root", "-silent", "-display", args.display], capture_output=True,
                                  check=True).stdout
            path = args.out if len(times) == 1 else args.out.replace(".png", f"_{t:.3f}s.png")
            matplotlib.image.imsave(path, xwd_to_rgb(dump))
            print(f"rviz_screenshot: {path} at t = {grabbed_at:.3f} s")
        return 0
    finally:
        if launch:
            railvib_process.stop(launch, grace_s=20.0)
        xvfb.terminate()
        xvfb.wait()


if __name__ == "__main__":
    sys.exit(main())
