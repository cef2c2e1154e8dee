// Where the simulation view hands its rendered frames: a small interface, so the simulator library
// encodes no video itself. The Python package implements it (vwg.video.VideoWriter: MP4 / GIF
// through PyAV); a C++ program can implement it with any encoder.
#pragma once

#include <opencv2/core.hpp>

namespace vwg::sim {

/// Receives the frames of one recording, in order, then close().
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  /// One frame: RGB (CV_8UC3), every frame of a recording the same size. The image is only valid
  /// during the call: a sink that keeps it copies it.
  virtual void write(const cv::Mat& rgb) = 0;
  /// The recording is over: finish the file. Called once, and only if write() was called.
  virtual void close() = 0;
};

}  // namespace vwg::sim
