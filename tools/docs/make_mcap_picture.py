"""docs/images/office_mcap.png: what an MCAP file of vwg's holds, drawn from the file alone. The office run to the
kitchen is written with --mcap; the file is read back with the MCAP project's reader and ROS 2 decoder (not vwg's
code) and Matplotlib draws /map, each robot's odometry track and ground truth, its last scan placed by its
odometry, its plan, and /rooms. (A screenshot of the Foxglove app itself cannot be made on our build machines,
which reach no web app; docs/ros.md says how to open the file there.)

    python tools/docs/make_mcap_picture.py [OUT.png]
"""

from __future__ import annotations

import math
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

COLOURS = {1: "#e4572e", 2: "#2e86ab"}


def main() -> None:
    default = Path(__file__).resolve().parents[2] / "docs/images/office_mcap.png"
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else default
    with tempfile.TemporaryDirectory() as tmp:
        mcap = Path(tmp) / "office.mcap"
        subprocess.run([sys.executable, "-m", "vwg", "run", "office", "--goal", "1:kitchen", "--goal", "2:lab",
                        "--mcap", str(mcap), "-q"], check=True)
        topics: dict[str, list] = defaultdict(list)
        with mcap.open("rb") as f:
            for _, channel, _, msg in make_reader(f, decoder_factories=[DecoderFactory()]).iter_decoded_messages():
                topics[channel.topic].append(msg)
    (known,) = topics["/map"]
    w, h, res = known.info.width, known.info.height, known.info.resolution
    ox, oy = known.info.origin.position.x, known.info.origin.position.y
    cells = np.asarray(known.data, np.int8).reshape(h, w)
    fig, ax = plt.subplots(figsize=(8, 6.4), dpi=110)
    ax.imshow(np.where(cells >= 50, 0.15, 0.97), cmap="gray", vmin=0, vmax=1, origin="lower",
              extent=(ox, ox + w * res, oy, oy + h * res))
    for robot, colour in COLOURS.items():
        odom = [m.pose.pose.position for m in topics[f"/robot{robot}/odom"]]
        truth = [m.pose.pose.position for m in topics[f"/robot{robot}/ground_truth"]]
        ax.plot([p.x for p in truth], [p.y for p in truth], color="black", lw=3, alpha=0.25)
        ax.plot([p.x for p in odom], [p.y for p in odom], color=colour, lw=1.5,
                label=f"/robot{robot}/odom (grey under it: ground_truth)")
        plan = topics[f"/robot{robot}/plan"][0]
        ax.plot([p.pose.position.x for p in plan.poses], [p.pose.position.y for p in plan.poses], color=colour,
                lw=1, ls="--", label=f"/robot{robot}/plan (the first)")
        # The scan taken halfway, placed by the odometry of its frame.
        scans = topics[f"/robot{robot}/scan"]
        k = len(scans) // 2
        scan, pose = scans[k], topics[f"/robot{robot}/odom"][k].pose.pose
        yaw = 2 * math.atan2(pose.orientation.z, pose.orientation.w)
        ranges = np.asarray(scan.ranges)
        angles = scan.angle_min + scan.angle_increment * np.arange(len(ranges)) + yaw
        hit = np.isfinite(ranges)
        xs = pose.position.x + ranges[hit] * np.cos(angles[hit])
        ys = pose.position.y + ranges[hit] * np.sin(angles[hit])
        ax.scatter(xs, ys, s=3, color=colour, label=f"/robot{robot}/scan (one, halfway)")
    for marker in topics["/rooms"][0].markers:
        if marker.type == 9:
            ax.annotate(marker.text, (marker.pose.position.x, marker.pose.position.y), ha="center", fontsize=9)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("vwg run office --mcap: the topics as the MCAP reader decodes them")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2, fontsize=8, frameon=False)
    fig.tight_layout()
    fig.savefig(out, bbox_inches="tight")
    print(out)


if __name__ == "__main__":
    main()
