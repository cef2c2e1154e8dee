#include "vwg/sim/sim_view.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <utility>

#include "vwg/error.hpp"
#include "vwg/semantics.hpp"

namespace vwg::sim {

SimView::SimView(std::shared_ptr<const platform::RobotPlatform> platform, OccupancyGrid grid, RenderStyle style,
                 platform::MotionSymbols symbols)
    : world_(std::move(platform)), grid_(std::move(grid)), renderer_(grid_, style), motion_(std::move(symbols)) {
  if (!world_) throw Error("SimView: no robot platform");
}

void SimView::add_marker(double x, double y, double facing, std::string label, int tag_id) {
  markers_.push_back(Marker{x, y, facing, std::move(label), tag_id});
}

void SimView::set_belief(int robot, std::vector<std::int8_t> cells) {
  if (cells.empty()) {
    beliefs_.erase(robot);
    return;
  }
  const auto& g = grid_;
  if (cells.size() != g.data.size()) throw SchemaError("belief", "expected one value per map cell");
  beliefs_[robot] = std::move(cells);
}

SimView::~SimView() {
  try {
    close();
  } catch (const std::exception& e) {
    // A destructor must not throw; the message is all that can be done for the caller.
    std::fprintf(stderr, "vwg: SimView: %s\n", e.what());
  }
}

void SimView::record_video(std::shared_ptr<FrameSink> sink) {
  close();  // a recording already going is finished first
  video_ = std::move(sink);
}

void SimView::record_images(const std::string& directory) { images_.emplace(directory); }

void SimView::close() {
  const std::shared_ptr<FrameSink> sink = std::exchange(video_, nullptr);
  const bool wrote = std::exchange(video_frames_, 0) > 0;
  if (sink && wrote) sink->close();
}

void SimView::begin_frame(const FrameInfo&) {
  motion_.begin_frame();
  commanded_.clear();
  paths_.clear();
  statuses_.clear();
}

void SimView::primitive(const NodeView& p) {
  int id = 0;
  std::vector<platform::MotionStep> plan;
  if (motion_.robot(p, id, plan)) {
    commanded_[id] = std::move(plan);
    return;
  }
  const std::string& name = p.info().name;
  if (name == "Path" && p.value_count() >= 2 && p.value(1).kind == ValueKind::Blob) {
    const std::span<const double> xy = p.store().blob(p.value(1))->view<double>();
    std::vector<cv::Point2d>& points = paths_[static_cast<int>(p.number(0))];
    points.clear();
    for (std::size_t k = 0; k + 1 < xy.size(); k += 2) points.emplace_back(xy[k], xy[k + 1]);
  } else if (name == "Status" && p.value_count() >= 2 && p.value(1).kind == ValueKind::Text) {
    statuses_[static_cast<int>(p.number(0))] = std::string(p.store().text(p.value(1)));
  }
}

std::string SimView::status_line() const {
  std::string line;
  for (const auto& [id, text] : statuses_) {
    std::string shown = text;
    for (const Marker& m : markers_) {  // "to marker 3" -> "to kitchen"
      const std::string key = "marker " + std::to_string(m.tag_id);
      const std::size_t at = shown.find(key);
      if (at != std::string::npos && (at + key.size() == shown.size() || shown[at + key.size()] == ' ')) {
        shown.replace(at, key.size(), m.label);
        break;
      }
    }
    line += (line.empty() ? "" : "   ") + std::to_string(id) + ": " + shown;
  }
  return line;
}

void SimView::end_frame(const FrameInfo& frame) {
  // Trajectories grow every frame, whether or not the robot was displayed.
  for (const RobotState& st : world_->robots()) trajectories_[st.id].emplace_back(st.pose.x, st.pose.y);
  last_frame_ = frame;
  if (!video_ && !images_) return;  // nothing to write: the trajectories are all that is kept
  draw(frame.frame, frame.time);
  write(1);
}

void SimView::finish(int hold_frames, const WorldString* final_view) {
  if (final_view) {
    begin_frame(last_frame_.value_or(FrameInfo{}));
    vwg::display(*final_view, *this);
  }
  if (last_frame_ && (video_ || images_)) {
    draw(last_frame_->frame, last_frame_->time);
    write(std::max(1, hold_frames));
  }
  close();  // later frames are not recorded: the video is finished
  images_.reset();
}

void SimView::draw(std::uint64_t frame, double time) {
  renderer_.begin(FrameText{static_cast<std::int64_t>(frame), time, status_line()});
  for (const auto& [id, cells] : beliefs_) {
    (void)id;
    renderer_.draw_belief(cells);
  }
  for (const Marker& m : markers_) renderer_.draw_marker(m.x, m.y, m.facing, m.label, m.tag_id);
  for (const auto& [id, points] : trajectories_) renderer_.draw_trajectory(points, id);
  for (const auto& [id, points] : paths_) renderer_.draw_path(points, id);
  std::vector<float> angles;
  // A sensor whose robot a λ took out of the string has no body, and its scan is not drawn.
  for (const auto& laser : lasers_) {
    const RobotState* robot = world_->find_robot(laser->robot());
    if (robot == nullptr) continue;
    angles.assign(laser->angles().begin(), laser->angles().end());
    renderer_.draw_scan(robot->pose, angles, laser->ranges(), laser->spec().max_range);
  }
  for (const auto& kinect : kinects_) {
    const RobotState* robot = world_->find_robot(kinect->robot());
    if (robot == nullptr) continue;
    angles.assign(kinect->angles().begin(), kinect->angles().end());
    renderer_.draw_scan(robot->pose, angles, kinect->ranges(), kinect->camera().spec().max_range);
  }
  // The simulator's people (a real robot's platform has none to draw).
  if (const auto* physics = dynamic_cast<const PhysicsWorld*>(world_.get())) {
    for (const PhysicsWorld::Person& p : physics->people()) renderer_.draw_person(p.x, p.y, p.radius);
  }
  // Robots displayed this frame (Table I: α(Robot) draws the robot); others are not drawn.
  for (const auto& [id, plan] : commanded_) {
    if (const RobotState* st = world_->find_robot(id)) renderer_.draw_robot(st->pose, st->radius, id);
  }
}

void SimView::write(int copies_to_video) {
  const cv::Mat& image = renderer_.image();
  if (video_) {
    for (int k = 0; k < copies_to_video; ++k) {
      video_->write(image);
      ++video_frames_;
    }
  }
  if (images_) images_->write(image);
  if (video_ || images_) ++written_;
}

}  // namespace vwg::sim
