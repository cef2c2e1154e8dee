// A range sensor's last scan as other parts of a run read it: the localization weighs its particles on
// it (vwg/robot/localization.hpp). The simulator's laser is one; a sensor of a plugin may be one too.
#pragma once

#include <span>

namespace vwg::platform {

/// One scan: each beam's range (max_range where nothing was hit) and its angle from the robot's heading.
struct ScanView {
  std::span<const float> ranges;
  std::span<const double> angles;
  double max_range = 0.0;
};

class ScanSource {
 public:
  virtual ~ScanSource() = default;
  /// The robot whose scans these are.
  virtual int scan_robot() const = 0;
  /// The scan of the last frame (empty before the first); valid until the sensor's next scan.
  virtual ScanView last_scan() const = 0;
};

}  // namespace vwg::platform
