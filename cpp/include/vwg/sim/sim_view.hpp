// The simulation drawn from above, as a backend (paper Table I, simulator column: "draw the robot
// in the GS"): each frame, the map, the room markers, every robot displayed by α(Robot<id>) at its
// true pose with its trajectory and latest scan, the paths and status lines displayed by
// α(Path<robot, points>) and α(Status<robot, text>) (what θ of the robot shows, through π and φ),
// and the beliefs the caller supplies; written to a video and/or PNG files. It keeps every robot's
// trajectory (the one place it is kept), drawing nothing when it writes nothing. Put it after the
// motion backend in a BackendGroup, so it draws the frame's motion.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vwg/backend.hpp"
#include "vwg/platform/motion.hpp"
#include "vwg/sim/depth_camera.hpp"
#include "vwg/sim/frame_sink.hpp"
#include "vwg/sim/image_io.hpp"
#include "vwg/sim/laser.hpp"
#include "vwg/sim/physics.hpp"
#include "vwg/sim/render2d.hpp"

namespace vwg::sim {

class SimView final : public Backend {
 public:
  /// The image's width and the text band above the map (pixels) when no RenderStyle is given, and
  /// how many times finish() writes the last frame to a video (a pause at its end).
  static constexpr int kDefaultWidth = 800, kDefaultHeader = 40, kDefaultHoldFrames = 10;
  /// The robots of `platform` (the simulator or a real robot's link) drawn on `grid`.
  SimView(std::shared_ptr<const platform::RobotPlatform> platform, OccupancyGrid grid, RenderStyle style = {},
          platform::MotionSymbols symbols = {});

  /// Scans to draw: a laser's or a Kinect's last scan, at its robot.
  void add_laser(std::shared_ptr<const LaserGenerator> laser) { lasers_.push_back(std::move(laser)); }
  void add_kinect(std::shared_ptr<const KinectGenerator> kinect) { kinects_.push_back(std::move(kinect)); }
  void add_marker(double x, double y, double facing, std::string label, int tag_id);
  /// A robot's belief grid (same geometry as the map), shown until replaced; empty removes it.
  void set_belief(int robot, std::vector<std::int8_t> cells);
  /// Where frames go: a video (any FrameSink: the Python package's MP4/GIF writer) and/or numbered
  /// PNG files. Without either, nothing is drawn and no sink is called.
  void record_video(std::shared_ptr<FrameSink> sink);
  void record_images(const std::string& directory);
  /// Finish the video: the sink's close(), if it was given frames (also done by the destructor);
  /// later frames are not recorded.
  void close();
  /// Draw the last frame again with what was set since (status, paths), write it `hold_frames`
  /// times to the video (once to the images), then close: a video's end shows the final state,
  /// such as a robot's arrival, which is only known after its frame was drawn.
  /// With `final_view` (π of the string the run ended with), that is what is drawn, so the end
  /// shows what the last frame's λ decided (an arrival) rather than what that frame displayed.
  void finish(int hold_frames = kDefaultHoldFrames, const WorldString* final_view = nullptr);

  void begin_frame(const FrameInfo& frame) override;
  void primitive(const NodeView& p) override;
  void open(const NodeView& t) override { motion_.open(t); }
  void close(const NodeView& t) override { motion_.close(t); }
  void end_frame(const FrameInfo& frame) override;
  std::string name() const override { return "view"; }
  ~SimView() override;

  /// The last frame drawn (RGB).
  const cv::Mat& image() { return renderer_.image(); }
  TopDownRenderer& renderer() { return renderer_; }
  std::int64_t frames_written() const { return written_; }
  /// Each robot's trajectory so far (true positions, one per frame).
  const std::map<int, std::vector<cv::Point2d>>& trajectories() const { return trajectories_; }

 private:
  void draw(std::uint64_t frame, double time);  // the frame into renderer_
  void write(int copies_to_video);              // renderer_'s image to the outputs

  struct Marker {
    double x, y, facing;
    std::string label;
    int tag_id;
  };
  std::shared_ptr<const platform::RobotPlatform> world_;
  OccupancyGrid grid_;
  TopDownRenderer renderer_;
  platform::MotionInterpreter motion_;
  std::vector<std::shared_ptr<const LaserGenerator>> lasers_;
  std::vector<std::shared_ptr<const KinectGenerator>> kinects_;
  std::vector<Marker> markers_;
  std::map<int, std::vector<cv::Point2d>> paths_;  // displayed this frame (α of Path)
  std::map<int, std::string> statuses_;            // displayed this frame (α of Status)
  std::map<int, std::vector<std::int8_t>> beliefs_;
  std::map<int, std::vector<cv::Point2d>> trajectories_;
  std::map<int, std::vector<platform::MotionStep>> commanded_;  // robots displayed this frame, with their plan
  std::string status_line() const;  // "1: to kitchen   2: idle", markers by their rooms' names
  std::shared_ptr<FrameSink> video_;
  std::int64_t video_frames_ = 0;  // frames handed to video_
  std::optional<ImageSequence> images_;
  std::int64_t written_ = 0;
  std::optional<FrameInfo> last_frame_;  // the last frame drawn, for finish()
};

}  // namespace vwg::sim
