#include "vwg/sim/render2d.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "vwg/error.hpp"

namespace vwg::sim {

namespace {

// OpenCV draws with integer coordinates; `shift` fractional bits keep sub-pixel positions, so thin
// rays and small discs do not jump by a pixel as a robot moves.
constexpr int kShift = 4;
constexpr double kOne = 1 << kShift;
// Beyond this many pixels a point is clamped: OpenCV's fixed-point coordinates would overflow.
constexpr double kFar = 1 << 20;
constexpr int kMaxSide = 16384;

cv::Scalar scalar(Rgb c) { return cv::Scalar(c.r, c.g, c.b); }

Rgb mix(Rgb a, Rgb b, double t) {
  auto lerp = [t](std::uint8_t x, std::uint8_t y) {
    return static_cast<std::uint8_t>(std::lround(x + (static_cast<double>(y) - x) * t));
  };
  return {lerp(a.r, b.r), lerp(a.g, b.g), lerp(a.b, b.b)};
}

bool finite(cv::Point2d p) { return std::isfinite(p.x) && std::isfinite(p.y); }

// Continuous pixel coordinates (pixel i covers [i, i+1)) to OpenCV's fixed point, where integer
// coordinates are pixel centres.
cv::Point fixed(cv::Point2d p) {
  const double x = std::clamp(p.x, -kFar, kFar) - 0.5, y = std::clamp(p.y, -kFar, kFar) - 0.5;
  return {static_cast<int>(std::lround(x * kOne)), static_cast<int>(std::lround(y * kOne))};
}

int fixed_len(double pixels) { return static_cast<int>(std::lround(std::max(pixels, 0.0) * kOne)); }

cv::Point2d unit(cv::Point2d v) {
  const double n = std::hypot(v.x, v.y);
  return n > 0 ? v * (1.0 / n) : cv::Point2d(1, 0);
}

}  // namespace

TopDownRenderer::TopDownRenderer(OccupancyGrid grid, RenderStyle style) : grid_(std::move(grid)), style_(std::move(style)) {
  if (grid_.width <= 0 || grid_.height <= 0) {
    throw Error("TopDownRenderer: the map is empty (" + std::to_string(grid_.width) + "×" +
                std::to_string(grid_.height) + " cells)");
  }
  if (grid_.data.size() != static_cast<std::size_t>(grid_.width) * grid_.height) {
    throw Error("TopDownRenderer: the map has " + std::to_string(grid_.data.size()) + " values, expected " +
                std::to_string(grid_.width) + "×" + std::to_string(grid_.height));
  }
  if (!(grid_.resolution > 0) || !std::isfinite(grid_.resolution)) {
    throw Error("TopDownRenderer: the map resolution must be positive, got " + std::to_string(grid_.resolution));
  }
  if (style_.margin < 0 || style_.header < 0) throw Error("TopDownRenderer: margin and header must be >= 0 pixels");
  const int m = style_.margin;
  int map_w = 0;
  if (style_.width > 0) {
    map_w = style_.width - 2 * m;
    if (map_w <= 0) {
      throw Error("TopDownRenderer: width " + std::to_string(style_.width) + " leaves no room for the map inside margins of " +
                  std::to_string(m));
    }
    ppc_ = static_cast<double>(map_w) / grid_.width;
  } else {
    ppc_ = style_.pixels_per_cell;
    if (!(ppc_ > 0) || !std::isfinite(ppc_)) {
      throw Error("TopDownRenderer: pixels_per_cell must be positive, got " + std::to_string(ppc_));
    }
    map_w = static_cast<int>(std::lround(grid_.width * ppc_));
  }
  const double map_h_exact = grid_.height * ppc_;
  if (map_w + 2 * m > kMaxSide || map_h_exact + 2 * m + style_.header > kMaxSide) {
    throw Error("TopDownRenderer: the image would be larger than " + std::to_string(kMaxSide) +
                " pixels on a side; lower pixels_per_cell or width");
  }
  const int map_h = std::max(1, static_cast<int>(std::lround(map_h_exact)));
  map_w = std::max(1, map_w);
  int img_w = map_w + 2 * m, img_h = map_h + 2 * m + style_.header;
  // The extra pixel goes to the right and top margins, so the map keeps its bottom-left corner.
  if (style_.even_size) {
    img_w += img_w % 2;
    img_h += img_h % 2;
  }
  map_rect_ = cv::Rect(m, img_h - m - map_h, map_w, map_h);

  // Pixel centres pick their cell, the same rule world_to_pixel follows.
  col_of_.resize(map_w);
  for (int i = 0; i < map_w; ++i) {
    col_of_[i] = std::clamp(static_cast<int>(std::floor((i + 0.5) / ppc_)), 0, grid_.width - 1);
  }
  row_of_.resize(map_h);
  for (int j = 0; j < map_h; ++j) {
    row_of_[j] = std::clamp(static_cast<int>(std::floor((map_h - (j + 0.5)) / ppc_)), 0, grid_.height - 1);
  }
  base_.create(img_h, img_w, CV_8UC3);
  draw_map_layer();
  begin();
}

void TopDownRenderer::update_map(std::span<const std::int8_t> cells) {
  if (cells.size() != grid_.data.size()) {
    throw Error("TopDownRenderer.update_map: " + std::to_string(cells.size()) + " values, the map has " +
                std::to_string(grid_.width) + "×" + std::to_string(grid_.height));
  }
  grid_.data.assign(cells.begin(), cells.end());
  draw_map_layer();
}

void TopDownRenderer::draw_map_layer() {
  base_.setTo(scalar(style_.background));
  // One colour per possible cell value: the per-pixel work is then a table look-up.
  std::array<Rgb, 256> lut{};
  for (int i = 0; i < 256; ++i) {
    const auto v = static_cast<std::int8_t>(static_cast<std::uint8_t>(i));
    if (v < 0) lut[i] = style_.unknown;
    else if (v == 0) lut[i] = style_.free;
    else if (v >= 100) lut[i] = style_.occupied;
    else lut[i] = mix(style_.free, style_.occupied, v / 100.0);
  }
  for (int j = 0; j < map_rect_.height; ++j) {
    const std::int8_t* cells = grid_.data.data() + static_cast<std::size_t>(row_of_[j]) * grid_.width;
    auto* px = base_.ptr<cv::Vec3b>(map_rect_.y + j) + map_rect_.x;
    for (int i = 0; i < map_rect_.width; ++i) {
      const Rgb c = lut[static_cast<std::uint8_t>(cells[col_of_[i]])];
      px[i] = cv::Vec3b(c.r, c.g, c.b);
    }
  }
}

void TopDownRenderer::begin(const FrameText& text) {
  base_.copyTo(canvas_);
  text_ = text;
  text_pending_ = true;
  labels_.clear();
  legend_.clear();
}

cv::Point2d TopDownRenderer::world_to_pixel(double x, double y) const {
  double u = 0, v = 0;
  grid_.world_to_grid(x, y, u, v);
  return {map_rect_.x + u * ppc_, map_rect_.y + map_rect_.height - v * ppc_};
}

Pose2 TopDownRenderer::pixel_to_world(double px, double py) const {
  const double u = (px - map_rect_.x) / ppc_, v = (map_rect_.y + map_rect_.height - py) / ppc_;
  Pose2 p;
  grid_.grid_to_world(u, v, p.x, p.y);
  return p;
}

Rgb RenderStyle::robot(int id) const {
  if (palette.empty()) return path;  // an emptied palette still draws robots
  const int n = static_cast<int>(palette.size());
  return palette[static_cast<std::size_t>(((id % n) + n) % n)];
}

Rgb TopDownRenderer::robot_colour(int id) const { return style_.robot(id); }

void TopDownRenderer::put_label(const std::string& text, cv::Point2d anchor, cv::Point2d away, cv::Point2d side) {
  if (text.empty() || !finite(anchor)) return;
  labels_.push_back(Label{text, anchor, away, side});
}

void TopDownRenderer::draw_label(const Label& label) {
  const std::string& text = label.text;
  const cv::Point2d anchor = label.anchor, away = label.away;
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double scale = style_.font_scale * 0.9;
  int baseline = 0;
  const cv::Size ts = cv::getTextSize(text, font, scale, 1, &baseline);
  // Centre the text beyond the anchor along `away`, far enough that its box clears the anchor,
  // then slide it along `side` (if any) by its own extent, so it starts at the anchor.
  const cv::Point2d d = unit(away);
  const double reach = 0.5 * (std::abs(d.x) * ts.width + std::abs(d.y) * ts.height) + 3.0;
  cv::Point2d centre = anchor + d * reach;
  if (label.side.x != 0 || label.side.y != 0) {
    const cv::Point2d sd = unit(label.side);
    centre += sd * (0.5 * (std::abs(sd.x) * ts.width + std::abs(sd.y) * ts.height));
  }
  double left = centre.x - ts.width / 2.0, base = centre.y + ts.height / 2.0;
  left = std::clamp(left, 1.0, std::max(1.0, canvas_.cols - ts.width - 1.0));
  base = std::clamp(base, ts.height + 1.0, std::max(ts.height + 1.0, canvas_.rows - baseline - 1.0));
  const cv::Point org(static_cast<int>(std::lround(left)), static_cast<int>(std::lround(base)));
  const int lt = style_.antialias ? cv::LINE_AA : cv::LINE_8;
  // A halo in the free colour keeps dark labels readable over walls and rays.
  cv::putText(canvas_, text, org, font, scale, scalar(style_.free), 3, lt);
  cv::putText(canvas_, text, org, font, scale, scalar(style_.label), 1, lt);
}

void TopDownRenderer::draw_robot(const Pose2& pose, double radius, int id, std::optional<std::string_view> label,
                                 std::optional<Rgb> colour) {
  const cv::Point2d c = world_to_pixel(pose.x, pose.y);
  if (!finite(c) || !std::isfinite(pose.theta)) return;
  const double r = std::max(std::isfinite(radius) ? radius * pixels_per_metre() : 0.0, style_.min_robot_px);
  const cv::Point2d d = unit(world_to_pixel(pose.x + std::cos(pose.theta), pose.y + std::sin(pose.theta)) - c);
  const int lt = style_.antialias ? cv::LINE_AA : cv::LINE_8;
  cv::circle(canvas_, fixed(c), fixed_len(r), scalar(colour.value_or(robot_colour(id))), cv::FILLED, lt, kShift);
  cv::circle(canvas_, fixed(c), fixed_len(r), scalar(style_.robot_outline), 1, lt, kShift);
  // The heading line starts off-centre: the centre keeps the robot's colour, which tests and
  // viewers use to find the robot.
  const int thick = std::max(1, static_cast<int>(std::lround(r / 4)));
  const double tip = std::max(r - thick / 2.0 - 0.5, 0.3 * r);
  cv::line(canvas_, fixed(c + d * (0.35 * r)), fixed(c + d * tip), scalar(style_.heading), thick, lt, kShift);
  const std::string text = label ? std::string(*label) : std::to_string(id);
  put_label(text, c + cv::Point2d(0.7071, -0.7071) * r, {1, -1});
}

void TopDownRenderer::draw_person(double x, double y, double radius) {
  const cv::Point2d c = world_to_pixel(x, y);
  if (!finite(c)) return;
  const double r = std::max(std::isfinite(radius) ? radius * pixels_per_metre() : 0.0, style_.min_robot_px);
  const int lt = style_.antialias ? cv::LINE_AA : cv::LINE_8;
  cv::circle(canvas_, fixed(c), fixed_len(r), scalar(style_.person), cv::FILLED, lt, kShift);
  cv::circle(canvas_, fixed(c), fixed_len(r), scalar(style_.robot_outline), 1, lt, kShift);
}

void TopDownRenderer::draw_scan(const Pose2& sensor, std::span<const float> angles, std::span<const float> ranges,
                                double max_range) {
  if (angles.size() != ranges.size()) {
    throw Error("TopDownRenderer.draw_scan: " + std::to_string(angles.size()) + " angles but " +
                std::to_string(ranges.size()) + " ranges");
  }
  const cv::Point2d o = world_to_pixel(sensor.x, sensor.y);
  if (!finite(o) || !std::isfinite(sensor.theta)) return;
  const int lt = style_.antialias ? cv::LINE_AA : cv::LINE_8;
  const double ppm = pixels_per_metre();
  // Angles in the image turn with the map's yaw and run clockwise (y points down).
  const double base = sensor.theta - grid_.origin.theta;
  auto end_of = [&](float angle, double range) {
    const double a = base + angle;
    return o + cv::Point2d(std::cos(a), -std::sin(a)) * (range * ppm);
  };
  auto is_hit = [&](float range) { return std::isfinite(range) && range >= 0 && range < max_range; };
  const cv::Point o_fixed = fixed(o);
  // Misses first, so the rays that hit something stay on top.
  if (style_.draw_misses && std::isfinite(max_range) && max_range > 0) {
    for (std::size_t i = 0; i < angles.size(); ++i) {
      if (is_hit(ranges[i]) || !std::isfinite(angles[i]) || (std::isfinite(ranges[i]) && ranges[i] < 0)) continue;
      cv::line(canvas_, o_fixed, fixed(end_of(angles[i], max_range)), scalar(style_.ray_miss), 1, lt, kShift);
    }
  }
  std::vector<cv::Point> hits;
  hits.reserve(angles.size());
  for (std::size_t i = 0; i < angles.size(); ++i) {
    if (!is_hit(ranges[i]) || !std::isfinite(angles[i])) continue;
    hits.push_back(fixed(end_of(angles[i], ranges[i])));
    cv::line(canvas_, o_fixed, hits.back(), scalar(style_.ray), 1, lt, kShift);
  }
  for (const cv::Point& h : hits) {
    cv::circle(canvas_, h, fixed_len(style_.hit_px), scalar(style_.hit), cv::FILLED, lt, kShift);
  }
}

void TopDownRenderer::draw_marker(double x, double y, double facing, std::string_view label, int tag_id) {
  const cv::Point2d c = world_to_pixel(x, y);
  if (!finite(c) || !std::isfinite(facing)) return;
  const int lt = style_.antialias ? cv::LINE_AA : cv::LINE_8;
  const double a = facing - grid_.origin.theta;
  const cv::Point2d f(std::cos(a), -std::sin(a));  // the way the marker looks, in the image
  const cv::Point2d along(-f.y, f.x);              // the wall
  const double half = std::max(style_.marker_length * pixels_per_metre() / 2, 3.0);
  const int thick = std::max(1, style_.marker_px);
  cv::line(canvas_, fixed(c - along * half), fixed(c + along * half), scalar(style_.marker), thick, lt, kShift);
  // A short tick shows which side of the wall the tag faces.
  const double tick = thick * 1.5 + 1;
  cv::line(canvas_, fixed(c), fixed(c + f * tick), scalar(style_.marker), std::max(1, thick / 2), lt, kShift);
  std::string text(label);
  if (tag_id >= 0) text += (text.empty() ? "#" : " #") + std::to_string(tag_id);
  // In front of the wall and beside the marker: the goal, where a robot stops, is straight ahead of it.
  put_label(text, c + along * half + f * tick, f, along);
}

void TopDownRenderer::draw_path(std::span<const cv::Point2d> points, int id) {
  const Rgb colour = id >= 0 ? robot_colour(id) : style_.path;
  const int lt = style_.antialias ? cv::LINE_AA : cv::LINE_8;
  const int thick = std::max(1, style_.path_px);
  // Non-finite points break the line rather than throwing: a planner may mark gaps that way.
  std::vector<cv::Point> run;
  auto flush = [&] {
    if (run.size() >= 2) cv::polylines(canvas_, run, false, scalar(colour), thick, lt, kShift);
    run.clear();
  };
  cv::Point2d last(std::nan(""), std::nan(""));
  for (const cv::Point2d& p : points) {
    const cv::Point2d q = world_to_pixel(p.x, p.y);
    if (!finite(q)) {
      flush();
      continue;
    }
    run.push_back(fixed(q));
    last = q;
  }
  flush();
  if (finite(last)) {
    cv::circle(canvas_, fixed(last), fixed_len(2.0 * thick + 2), scalar(colour), thick, lt, kShift);
  }
}

void TopDownRenderer::draw_trajectory(std::span<const cv::Point2d> points, int id) {
  std::vector<cv::Point> pts;
  pts.reserve(points.size());
  for (const cv::Point2d& p : points) {
    const cv::Point2d q = world_to_pixel(p.x, p.y);
    if (finite(q)) pts.push_back(fixed(q));
  }
  if (pts.size() < 2) return;
  const Rgb full = id >= 0 ? robot_colour(id) : style_.trajectory;
  const double faint = std::clamp(style_.trajectory_faint, 0.0, 1.0);
  const int lt = style_.antialias ? cv::LINE_AA : cv::LINE_8;
  const int thick = std::max(1, style_.trajectory_px);
  const std::size_t n = pts.size();
  const std::size_t window = static_cast<std::size_t>(std::max(1, style_.trajectory_fade));
  const std::size_t start = n - 1 > window ? n - 1 - window : 0;  // first point of the fading part
  auto draw = [&](std::size_t from, std::size_t to, double strength) {  // points [from, to]
    if (to <= from) return;
    const std::vector<cv::Point> part(pts.begin() + static_cast<std::ptrdiff_t>(from),
                                      pts.begin() + static_cast<std::ptrdiff_t>(to) + 1);
    cv::polylines(canvas_, part, false, scalar(mix(style_.free, full, strength)), thick, lt, kShift);
  };
  draw(0, start, faint);
  // The fade in a few bands of one colour each: one polyline per band instead of one line per
  // segment keeps long trails cheap.
  const std::size_t bands = std::min<std::size_t>(12, n - 1 - start);
  for (std::size_t k = 0; k < bands; ++k) {
    const std::size_t from = start + (n - 1 - start) * k / bands, to = start + (n - 1 - start) * (k + 1) / bands;
    draw(from, to, faint + (1.0 - faint) * static_cast<double>(k + 1) / static_cast<double>(bands));
  }
}

void TopDownRenderer::draw_belief(std::span<const std::int8_t> cells) {
  if (cells.size() != grid_.data.size()) {
    throw Error("TopDownRenderer.draw_belief: " + std::to_string(cells.size()) + " cells, the map has " +
                std::to_string(grid_.width) + "×" + std::to_string(grid_.height) + " = " +
                std::to_string(grid_.data.size()));
  }
  // Colour and opacity (0..256) per cell value, from free to occupied; unknown stays transparent.
  struct Tint {
    int r, g, b, a;
  };
  std::array<Tint, 256> lut{};
  for (int i = 0; i < 256; ++i) {
    const auto v = static_cast<std::int8_t>(static_cast<std::uint8_t>(i));
    if (v < 0) continue;
    const double t = std::min<int>(v, 100) / 100.0;
    const Rgb c = mix(style_.belief_free, style_.belief_occupied, t);
    const double alpha = style_.belief_free_alpha + (style_.belief_occupied_alpha - style_.belief_free_alpha) * t;
    lut[i] = {c.r, c.g, c.b, static_cast<int>(std::lround(std::clamp(alpha, 0.0, 1.0) * 256))};
  }
  for (int j = 0; j < map_rect_.height; ++j) {
    const std::int8_t* row = cells.data() + static_cast<std::size_t>(row_of_[j]) * grid_.width;
    auto* px = canvas_.ptr<cv::Vec3b>(map_rect_.y + j) + map_rect_.x;
    for (int i = 0; i < map_rect_.width; ++i) {
      const Tint& t = lut[static_cast<std::uint8_t>(row[col_of_[i]])];
      if (t.a == 0) continue;
      cv::Vec3b& p = px[i];
      p[0] = static_cast<std::uint8_t>((p[0] * (256 - t.a) + t.r * t.a) >> 8);
      p[1] = static_cast<std::uint8_t>((p[1] * (256 - t.a) + t.g * t.a) >> 8);
      p[2] = static_cast<std::uint8_t>((p[2] * (256 - t.a) + t.b * t.a) >> 8);
    }
  }
}

void TopDownRenderer::draw_corner_text() {
  std::vector<std::string> lines;
  std::string head;
  char buf[64];
  if (text_.frame >= 0) {
    std::snprintf(buf, sizeof buf, "frame %lld", static_cast<long long>(text_.frame));
    head = buf;
  }
  if (std::isfinite(text_.time)) {
    std::snprintf(buf, sizeof buf, "t = %.2f s", text_.time);
    head += (head.empty() ? "" : "   ") + std::string(buf);
  }
  if (!head.empty()) lines.push_back(head);
  std::size_t from = 0;
  while (from < text_.status.size()) {  // the status may hold several lines
    const std::size_t nl = std::min(text_.status.find('\n', from), text_.status.size());
    if (nl > from) lines.push_back(text_.status.substr(from, nl - from));
    from = nl + 1;
  }
  if (lines.empty()) return;
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double scale = style_.font_scale;
  int baseline = 0, width = 0, height = 0;
  for (const std::string& l : lines) {
    const cv::Size s = cv::getTextSize(l, font, scale, 1, &baseline);
    width = std::max(width, s.width);
    height = std::max(height, s.height);
  }
  const int pad = 4, step = height + baseline + 3;
  cv::Rect box(2, 2, width + 2 * pad, static_cast<int>(lines.size()) * step + 2 * pad - 3);
  box &= cv::Rect(0, 0, canvas_.cols, canvas_.rows);
  if (box.area() > 0 && style_.text_box_alpha > 0) {
    // Translucent, so the map under the corner stays visible.
    cv::Mat roi = canvas_(box);
    const cv::Mat fill(roi.size(), roi.type(), scalar(style_.text_box));
    const double a = std::clamp(style_.text_box_alpha, 0.0, 1.0);
    cv::addWeighted(roi, 1.0 - a, fill, a, 0.0, roi);
  }
  const int lt = style_.antialias ? cv::LINE_AA : cv::LINE_8;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const cv::Point org(box.x + pad, box.y + pad + height + static_cast<int>(i) * step);
    cv::putText(canvas_, lines[i], org, font, scale, scalar(style_.text), 1, lt);
  }
}

void TopDownRenderer::draw_start(double x, double y, int id) {
  const cv::Point2d c = world_to_pixel(x, y);
  if (!finite(c)) return;
  const double h = std::max(4.0, 0.15 * pixels_per_metre());
  const cv::Rect2d box(c.x - h, c.y - h, 2 * h, 2 * h);
  const int lt = style_.antialias ? cv::LINE_AA : cv::LINE_8;
  cv::rectangle(canvas_, fixed(box.tl()), fixed(box.br()), scalar(style_.robot_outline), 4, lt, kShift);
  cv::rectangle(canvas_, fixed(box.tl()), fixed(box.br()), scalar(robot_colour(id)), 2, lt, kShift);
}

void TopDownRenderer::draw_legend(std::vector<LegendEntry> entries) { legend_ = std::move(entries); }

void TopDownRenderer::draw_legend_box() {
  if (legend_.empty()) return;
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double scale = style_.font_scale;
  const std::string key = "start        final pose";
  int baseline = 0, width = cv::getTextSize(key, font, scale, 1, &baseline).width + 16, height = 0;
  for (const LegendEntry& e : legend_) {
    const cv::Size s = cv::getTextSize(e.text, font, scale, 1, &baseline);
    width = std::max(width, s.width + 22);
    height = std::max(height, s.height);
  }
  const int pad = 5, step = height + baseline + 5, rows = static_cast<int>(legend_.size()) + 1;
  cv::Rect box(canvas_.cols - width - 2 * pad - 2, 2, width + 2 * pad, rows * step + 2 * pad - 3);
  box &= cv::Rect(0, 0, canvas_.cols, canvas_.rows);
  if (box.area() <= 0) return;
  cv::Mat roi = canvas_(box);
  const cv::Mat fill(roi.size(), roi.type(), scalar(style_.text_box));
  const double a = std::clamp(std::max(style_.text_box_alpha, 0.75), 0.0, 1.0);
  cv::addWeighted(roi, 1.0 - a, fill, a, 0.0, roi);
  const int lt = style_.antialias ? cv::LINE_AA : cv::LINE_8;
  for (std::size_t i = 0; i <= legend_.size(); ++i) {
    const int base = box.y + pad + height + static_cast<int>(i) * step;
    const cv::Point swatch(box.x + pad, base - height / 2);
    if (i < legend_.size()) {
      const Rgb c = robot_colour(legend_[i].id);
      cv::line(canvas_, swatch, swatch + cv::Point(14, 0), scalar(c), 3, lt);
      cv::putText(canvas_, legend_[i].text, {box.x + pad + 20, base}, font, scale, scalar(style_.text), 1, lt);
    } else {  // the key of the marks: a hollow square, then a disc
      const int h = std::max(3, height / 2);
      cv::rectangle(canvas_, swatch + cv::Point(3 - h, -h), swatch + cv::Point(3 + h, h), scalar(style_.text), 1, lt);
      const int x2 = box.x + pad + 20 + cv::getTextSize("start  ", font, scale, 1, &baseline).width + 6;
      cv::circle(canvas_, {x2 + h, base - height / 2}, h, scalar(style_.text), cv::FILLED, lt);
      cv::putText(canvas_, "start", {box.x + pad + 20, base}, font, scale, scalar(style_.text), 1, lt);
      cv::putText(canvas_, "final pose", {x2 + 2 * h + 6, base}, font, scale, scalar(style_.text), 1, lt);
    }
  }
}

const cv::Mat& TopDownRenderer::image() {
  // Overlays go on last, in this order: labels, the legend, the corner text.
  for (const Label& l : labels_) draw_label(l);
  labels_.clear();
  draw_legend_box();
  legend_.clear();
  if (text_pending_) {
    draw_corner_text();
    text_pending_ = false;
  }
  return canvas_;
}

}  // namespace vwg::sim
