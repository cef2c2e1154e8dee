"""Perception: AprilTag detection and pose (the markers that name the rooms), image sources (files,
video, a simulated camera) and gCamera, the generator that turns what a camera sees into eCamera
events.

    for tag in vwg.perception.detect_apriltags(grey_image):
        print(tag.id, tag.centre)
"""

from __future__ import annotations

from vwg._core import (
    AprilTagDetection,
    AprilTagFamily,
    AprilTagPose,
    CameraGenerator,
    ImageFiles,
    VideoSource,
    apriltag_families,
    apriltag_family,
    apriltag_image,
    detect_apriltags,
    estimate_tag_pose,
)

__all__ = ["AprilTagDetection", "AprilTagFamily", "AprilTagPose", "CameraGenerator", "ImageFiles", "VideoSource",
           "apriltag_families", "apriltag_family", "apriltag_image", "detect_apriltags", "estimate_tag_pose"]
