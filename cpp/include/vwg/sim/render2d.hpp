// The 2D top-down renderer of the robot simulator: one RGB image per frame showing the map, the
// robots, their laser rays, the wall markers, planned paths, trajectories and the robot's own map.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>

#include "vwg/sim/grid.hpp"

namespace vwg::sim {

/// An 8-bit RGB colour (the canvas is RGB, like vwg's image I/O, not OpenCV's BGR).
struct Rgb {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;  ///< channel by channel
};

/// Size, colours and line widths of a TopDownRenderer. Pixel sizes are in image pixels; lengths
/// in metres where the name says so.
struct RenderStyle {
  // --- size ---
  double pixels_per_cell = 4.0;  ///< scale; ignored when `width` > 0
  int width = 0;                 ///< > 0: total image width in pixels, margins included (sets the scale)
  int margin = 8;                ///< pixels of background around the map
  int header = 0;                ///< extra pixels above the map for the corner text (0: it covers the map's corner)
  bool even_size = true;         ///< round the image up to an even width and height (H.264 yuv420p needs them)
  bool antialias = true;         ///< smooth lines, discs and text (LINE_AA)

  // --- the map: free, occupied and unknown cells; values 1..99 ("scale" maps) as greys between ---
  Rgb background{58, 63, 72};
  Rgb free{246, 246, 242};
  Rgb occupied{40, 42, 48};
  Rgb unknown{176, 182, 190};

  // --- robots: robot `id` takes palette[id mod size] (Tableau 10, readable on light and dark) ---
  std::vector<Rgb> palette{{31, 119, 180}, {255, 127, 14}, {44, 160, 44},  {214, 39, 40},  {148, 103, 189},
                           {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
  Rgb robot_outline{20, 20, 24};
  Rgb heading{255, 255, 255};
  Rgb person{222, 184, 135};  ///< people who walk (vwg/sim/people.hpp): sand
  /// Robot `id`'s colour: palette[id mod its size] (the path colour if the palette is empty).
  Rgb robot(int id) const;
  /// A body's colour where robots and people are given as bodies, people with the id −(their id) (the 3D
  /// views, the robot camera): robot(id), or `person` for an id below zero.
  Rgb body(int id) const { return id < 0 ? person : robot(id); }
  double min_robot_px = 4.0;  ///< a robot is never drawn smaller than this radius, so it stays visible

  // --- laser scans ---
  Rgb ray{255, 170, 170};
  Rgb ray_miss{236, 226, 226};  ///< rays that reached the maximum range (faint)
  bool draw_misses = true;      ///< false: skip max-range rays altogether
  Rgb hit{220, 30, 30};
  int hit_px = 2;  ///< radius of a hit point

  // --- planned paths and trajectories ---
  Rgb path{0, 150, 110};  ///< for paths drawn without a robot id
  int path_px = 2;
  Rgb trajectory{90, 90, 200};  ///< for trajectories drawn without a robot id
  int trajectory_px = 2;
  int trajectory_fade = 150;    ///< the newest this many points fade in; older ones are drawn faint
  double trajectory_faint = 0.25;  ///< strength (0..1, 1 = full colour) of the oldest part

  // --- wall markers (AprilTags on walls) ---
  Rgb marker{230, 150, 0};
  int marker_px = 4;           ///< thickness of the segment
  double marker_length = 0.3;  ///< metres along the wall

  // --- the robot's belief (its own occupancy grid), blended over the map ---
  Rgb belief_occupied{20, 90, 230};
  double belief_occupied_alpha = 0.6;
  Rgb belief_free{110, 180, 255};
  double belief_free_alpha = 0.22;

  // --- text (frame, time, status line in the top-left corner; labels) ---
  Rgb text{250, 250, 250};
  Rgb text_box{20, 22, 28};
  double text_box_alpha = 0.6;
  double font_scale = 0.45;  ///< OpenCV Hershey simplex font; ~14 px line height at 0.45
  Rgb label{20, 20, 24};     ///< robot and marker labels, drawn on the map
};

/// What the corner text shows for a frame: "frame N  t = T s" and a status line (each part
/// omitted when unset).
struct FrameText {
  std::int64_t frame = -1;  ///< < 0: not shown
  double time = std::numeric_limits<double>::quiet_NaN();  ///< NaN: not shown
  std::string status;
};

/// Draws frames of the 2D simulation into an RGB canvas with y up: the map's bottom row is at the
/// image bottom. The static map is drawn once into a cached layer and copied at begin(), so a frame
/// costs its moving parts only. Not thread-safe (one renderer per thread).
///
///     TopDownRenderer r(grid);
///     r.begin({.frame = 12, .time = 1.2});
///     r.draw_scan(robot, angles, ranges, 8.0);
///     r.draw_robot(robot, 0.18, 1);
///     write_image("frame.png", r.image());
class TopDownRenderer {
 public:
  /// Throws vwg::Error for an empty grid, a data size that is not width × height, a non-positive
  /// resolution or scale, or an image larger than 16384 pixels on a side.
  explicit TopDownRenderer(OccupancyGrid grid, RenderStyle style = {});

  /// Replace the map's cell values (same width and height) and redraw the cached layer.
  void update_map(std::span<const std::int8_t> cells);

  /// An id that names no robot (a path or trajectory in the style's own colour) or no tag.
  static constexpr int kNoId = -1;
  /// The robot a disc is drawn for when none is said (palette colour 0).
  static constexpr int kDefaultRobotId = 0;

  /// Start a frame: the map layer, and the corner text drawn on top when the frame is read.
  void begin(const FrameText& text = {});

  /// A disc of `radius` metres at the pose with a heading line, in robot `id`'s colour (or
  /// `colour`), labelled with the id (or `label`; an empty label draws none).
  void draw_robot(const Pose2& pose, double radius, int id = kDefaultRobotId, std::optional<std::string_view> label = std::nullopt,
                  std::optional<Rgb> colour = std::nullopt);

  /// Laser rays from `sensor`: angles (radians, relative to the sensor's heading) and ranges
  /// (metres). A range that is not finite or reaches `max_range` is a miss: a faint ray to
  /// max_range (or nothing, see RenderStyle::draw_misses); others end in a hit point.
  /// Throws vwg::Error when the spans differ in length.
  /// A person (vwg/sim/people.hpp): a sand-coloured disc with an outline and no heading (robots are the palette's).
  void draw_person(double x, double y, double radius);
  void draw_scan(const Pose2& sensor, std::span<const float> angles, std::span<const float> ranges,
                 double max_range = std::numeric_limits<double>::infinity());

  /// A marker on a wall at (x, y) whose face looks towards `facing` (radians): a thick segment
  /// along the wall, and the label (e.g. the room name) with " #tag_id" when tag_id >= 0, on the
  /// side it faces.
  void draw_marker(double x, double y, double facing, std::string_view label = {}, int tag_id = kNoId);

  /// A planned path: a polyline through world points (metres), ending in a ring at the goal, in
  /// robot `id`'s colour (id < 0: RenderStyle::path).
  void draw_path(std::span<const cv::Point2d> points, int id = kNoId);

  /// A trajectory (oldest point first): a thin polyline that fades from the newest point back.
  void draw_trajectory(std::span<const cv::Point2d> points, int id = kNoId);

  /// Where robot `id` started: a hollow square in its colour (the legend names it "start").
  void draw_start(double x, double y, int id);

  /// A legend in the top-right corner: one line per entry, each with a swatch in robot `id`'s
  /// colour, and a last line explaining the start square and the final disc. Drawn on top.
  struct LegendEntry {
    int id = 0;
    std::string text;
  };
  void draw_legend(std::vector<LegendEntry> entries);

  /// The robot's belief: an int8 grid of the map's geometry (-1 unknown, 0 free .. 100 occupied)
  /// blended over the map; unknown cells leave the map visible. Throws vwg::Error on a size mismatch.
  void draw_belief(std::span<const std::int8_t> cells);

  /// The finished frame (RGB, CV_8UC3). Labels (of robots and markers), the legend and the corner
  /// text are drawn when the frame is read, so they stay on top of rays, paths and robots. Valid
  /// until the next begin().
  const cv::Mat& image();

  /// Continuous pixel coordinates of a world point: pixel (i, j) covers [i, i+1) × [j, j+1), so
  /// the map's lower-left corner is at (margin, height - margin).
  cv::Point2d world_to_pixel(double x, double y) const;
  /// The inverse of world_to_pixel.
  Pose2 pixel_to_world(double px, double py) const;

  /// The image size (constant for a renderer, so its frames can go into one video).
  cv::Size size() const { return base_.size(); }
  /// The scale, in image pixels per map cell and per metre.
  double pixels_per_cell() const { return ppc_; }
  double pixels_per_metre() const { return ppc_ / grid_.resolution; }
  /// Where the map lies in the image (the rest is margin).
  cv::Rect map_rect() const { return map_rect_; }
  /// The map drawn, and the settings it was drawn with.
  const OccupancyGrid& grid() const { return grid_; }
  const RenderStyle& style() const { return style_; }
  /// The colour of robot `id` (palette[id mod size]; negative ids count from the end).
  Rgb robot_colour(int id) const;

 private:
  struct Label {
    std::string text;
    cv::Point2d anchor, away, side;
  };
  void draw_map_layer();
  void draw_corner_text();
  void draw_legend_box();
  // Deferred to image(): the text beyond `anchor` along `away`, and slid along `side` if non-zero.
  void put_label(const std::string& text, cv::Point2d anchor, cv::Point2d away, cv::Point2d side = {0, 0});
  void draw_label(const Label& label);

  OccupancyGrid grid_;
  RenderStyle style_;
  double ppc_ = 0.0;         // pixels per cell
  cv::Rect map_rect_;        // the map's pixels
  std::vector<int> col_of_;  // for each pixel column of map_rect_, its grid column
  std::vector<int> row_of_;  // for each pixel row of map_rect_ (top first), its grid row
  cv::Mat base_;             // the cached static layer: background and map
  cv::Mat canvas_;           // the frame being drawn
  FrameText text_;
  bool text_pending_ = false;
  std::vector<Label> labels_;               // drawn by image(), on top
  std::vector<LegendEntry> legend_;         // drawn by image(), on top
};

}  // namespace vwg::sim
