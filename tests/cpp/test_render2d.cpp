// The 2D top-down renderer, image sequences and the view's frame sink. Expected pixels and sizes are worked out by hand
// from the geometry written in each test (pixel i covers [i, i+1); map bottom at image bottom).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "vwg/error.hpp"
#include "vwg/sim/image_io.hpp"
#include "vwg/sim/render2d.hpp"
#include "vwg/sim/frame_sink.hpp"
#include "vwg/sim/physics.hpp"
#include "vwg/sim/sim_view.hpp"

using namespace vwg;
using namespace vwg::sim;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = std::numbers::pi;

/// 20 × 10 cells of 0.1 m (2 m × 1 m), all free.
OccupancyGrid free_grid(Pose2 origin = {}) {
  OccupancyGrid g;
  g.width = 20;
  g.height = 10;
  g.resolution = 0.1;
  g.origin = origin;
  g.data.assign(200, kFree);
  return g;
}

/// Plain colours, so expected pixels are simple numbers.
RenderStyle plain_style() {
  RenderStyle s;
  s.pixels_per_cell = 4;
  s.margin = 8;
  s.background = {0, 0, 255};
  s.free = {255, 255, 255};
  s.occupied = {0, 0, 0};
  s.unknown = {128, 0, 128};
  s.palette = {{10, 20, 30}, {40, 50, 60}, {200, 100, 0}};
  s.heading = {250, 250, 0};
  s.hit = {255, 0, 0};
  s.ray = {0, 255, 0};
  s.ray_miss = {0, 200, 200};
  s.path = {0, 120, 0};
  s.marker = {255, 128, 0};
  s.belief_occupied = {0, 0, 255};
  s.belief_occupied_alpha = 0.5;
  s.text_box = {0, 0, 0};
  s.text_box_alpha = 0.5;
  return s;
}

Rgb pixel(const cv::Mat& image, int x, int y) {
  const auto p = image.at<cv::Vec3b>(y, x);
  return {p[0], p[1], p[2]};
}

::testing::AssertionResult near(Rgb got, Rgb want, int tolerance) {
  auto off = [](int a, int b) { return std::abs(a - b); };
  if (off(got.r, want.r) <= tolerance && off(got.g, want.g) <= tolerance && off(got.b, want.b) <= tolerance) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "got (" << int(got.r) << ", " << int(got.g) << ", " << int(got.b)
                                       << "), want (" << int(want.r) << ", " << int(want.g) << ", " << int(want.b)
                                       << ") ± " << tolerance;
}

/// A fresh folder per test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("vwg_render_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// A frame filled with one colour, a different one per index.
cv::Mat solid_frame(int w, int h, int i) {
  return cv::Mat(h, w, CV_8UC3, cv::Scalar(40 + 20 * (i % 10), 200 - 15 * (i % 10), 90));
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

// ---------------------------------------------------------------- geometry

TEST(TopDownRenderer, SizeFromPixelsPerCell) {
  TopDownRenderer r(free_grid(), plain_style());
  // 20 cells × 4 px + 2 × 8 margin; 10 × 4 + 16.
  EXPECT_EQ(r.size(), cv::Size(96, 56));
  EXPECT_EQ(r.map_rect(), cv::Rect(8, 8, 80, 40));
  EXPECT_DOUBLE_EQ(r.pixels_per_metre(), 40.0);
}

TEST(TopDownRenderer, SizeFromWidth) {
  RenderStyle s = plain_style();
  s.width = 216;  // 200 px of map for 20 cells: 10 px per cell; 10 rows: 100 px + 16
  TopDownRenderer r(free_grid(), s);
  EXPECT_EQ(r.size(), cv::Size(216, 116));
  EXPECT_DOUBLE_EQ(r.pixels_per_cell(), 10.0);
}

TEST(TopDownRenderer, EvenSizeAddsToTheTopAndRight) {
  OccupancyGrid g = free_grid();
  g.width = 5;
  g.height = 3;
  g.data.assign(15, kFree);
  RenderStyle s = plain_style();
  s.pixels_per_cell = 3;
  s.margin = 0;
  TopDownRenderer even(g, s);  // 15 × 9 rounds up to 16 × 10
  EXPECT_EQ(even.size(), cv::Size(16, 10));
  EXPECT_EQ(even.map_rect(), cv::Rect(0, 1, 15, 9));
  EXPECT_EQ(even.world_to_pixel(0, 0), cv::Point2d(0, 10));
  s.even_size = false;
  TopDownRenderer odd(g, s);
  EXPECT_EQ(odd.size(), cv::Size(15, 9));
}

TEST(TopDownRenderer, HeaderAddsRoomAboveTheMap) {
  RenderStyle s = plain_style();
  s.header = 30;
  TopDownRenderer r(free_grid(), s);
  EXPECT_EQ(r.size(), cv::Size(96, 86));
  EXPECT_EQ(r.map_rect(), cv::Rect(8, 38, 80, 40));
  EXPECT_EQ(r.world_to_pixel(0, 0), cv::Point2d(8, 78));
}

TEST(TopDownRenderer, WorldToPixelPutsTheMapBottomLeftAtTheImageBottomLeft) {
  TopDownRenderer r(free_grid(), plain_style());
  EXPECT_EQ(r.world_to_pixel(0, 0), cv::Point2d(8, 48));       // lower-left corner of the map
  EXPECT_EQ(r.world_to_pixel(2.0, 1.0), cv::Point2d(88, 8));   // upper-right corner
  const cv::Point2d c = r.world_to_pixel(0.05, 0.05);          // centre of cell (0, 0)
  EXPECT_NEAR(c.x, 10.0, 1e-9);
  EXPECT_NEAR(c.y, 46.0, 1e-9);
  const Pose2 back = r.pixel_to_world(10, 46);
  EXPECT_NEAR(back.x, 0.05, 1e-12);
  EXPECT_NEAR(back.y, 0.05, 1e-12);
}

TEST(TopDownRenderer, WorldToPixelFollowsTheOrigin) {
  TopDownRenderer r(free_grid({-1.0, 2.0, 0.0}), plain_style());
  EXPECT_EQ(r.world_to_pixel(-1.0, 2.0), cv::Point2d(8, 48));
  const cv::Point2d p = r.world_to_pixel(0.0, 2.5);  // 10 cells right, 5 up: 8 + 40, 48 - 20
  EXPECT_NEAR(p.x, 48.0, 1e-9);
  EXPECT_NEAR(p.y, 28.0, 1e-9);
}

TEST(TopDownRenderer, WorldToPixelFollowsARotatedOrigin) {
  // The map's x axis points along world +y: world (0, 1) is 10 cells along the map's x.
  TopDownRenderer r(free_grid({0.0, 0.0, kPi / 2}), plain_style());
  const cv::Point2d p = r.world_to_pixel(0.0, 1.0);
  EXPECT_NEAR(p.x, 48.0, 1e-9);
  EXPECT_NEAR(p.y, 48.0, 1e-9);
  const cv::Point2d q = r.world_to_pixel(-0.5, 0.0);  // 5 cells along the map's y: up 20 px
  EXPECT_NEAR(q.x, 8.0, 1e-9);
  EXPECT_NEAR(q.y, 28.0, 1e-9);
}

TEST(TopDownRenderer, RejectsBadGrids) {
  OccupancyGrid g = free_grid();
  g.data.pop_back();
  EXPECT_THROW(TopDownRenderer(g, plain_style()), Error);
  OccupancyGrid empty;
  EXPECT_THROW(TopDownRenderer(empty, plain_style()), Error);
  RenderStyle s = plain_style();
  s.pixels_per_cell = 0;
  EXPECT_THROW(TopDownRenderer(free_grid(), s), Error);
  s = plain_style();
  s.width = 10;  // less than the margins
  EXPECT_THROW(TopDownRenderer(free_grid(), s), Error);
}

// ---------------------------------------------------------------- pixels

TEST(TopDownRenderer, MapCellsHaveTheirColours) {
  OccupancyGrid g = free_grid();
  g.data[0] = kOccupied;             // row 0, column 0: bottom-left
  g.data[9 * 20 + 19] = kUnknown;    // row 9, column 19: top-right
  g.data[5 * 20 + 5] = 50;           // half way between free and occupied
  TopDownRenderer r(g, plain_style());
  const cv::Mat& im = r.image();
  ASSERT_EQ(im.type(), CV_8UC3);
  EXPECT_EQ(pixel(im, 10, 46), (Rgb{0, 0, 0}));        // cell (0,0): x 8..11, y 44..47
  EXPECT_EQ(pixel(im, 86, 10), (Rgb{128, 0, 128}));    // cell (9,19): x 84..87, y 8..11
  EXPECT_EQ(pixel(im, 30, 26), (Rgb{128, 128, 128}));  // cell (5,5): x 28..31, y 24..27; 255 / 2 rounded
  EXPECT_EQ(pixel(im, 14, 46), (Rgb{255, 255, 255}));  // cell (0,1) is free
  EXPECT_EQ(pixel(im, 2, 2), (Rgb{0, 0, 255}));        // margin
  EXPECT_EQ(pixel(im, 95, 55), (Rgb{0, 0, 255}));
}

TEST(TopDownRenderer, UpdateMapRedrawsTheLayer) {
  TopDownRenderer r(free_grid(), plain_style());
  std::vector<std::int8_t> cells(200, kFree);
  cells[0] = kOccupied;
  r.update_map(cells);
  r.begin();
  EXPECT_EQ(pixel(r.image(), 10, 46), (Rgb{0, 0, 0}));
  EXPECT_THROW(r.update_map(std::vector<std::int8_t>(10, 0)), Error);
}

TEST(TopDownRenderer, RobotColoursItsCentreAndShowsItsHeading) {
  TopDownRenderer r(free_grid(), plain_style());
  r.begin();
  // (1.0, 0.5) is pixel corner (48, 28); radius 0.2 m = 8 px; heading up, in the image too.
  r.draw_robot({1.0, 0.5, kPi / 2}, 0.2, 2);
  const cv::Mat& im = r.image();
  EXPECT_EQ(pixel(im, 48, 28), (Rgb{200, 100, 0}));  // palette[2]
  EXPECT_EQ(pixel(im, 47, 30), (Rgb{200, 100, 0}));
  // The heading line: x 47..48 (2 px wide around x = 48), from 2.8 px to 6.5 px above the centre.
  EXPECT_TRUE(near(pixel(im, 48, 23), {250, 250, 0}, 40));
  EXPECT_EQ(pixel(im, 48, 36 + 2), (Rgb{255, 255, 255}));  // 10 px below the centre: outside the disc
}

TEST(TopDownRenderer, RobotColourFromPaletteWrapsAndCanBeGiven) {
  TopDownRenderer r(free_grid(), plain_style());
  EXPECT_EQ(r.robot_colour(3), (Rgb{10, 20, 30}));   // 3 mod 3
  EXPECT_EQ(r.robot_colour(-1), (Rgb{200, 100, 0}));
  r.begin();
  r.draw_robot({1.0, 0.5, kPi / 2}, 0.2, 0, "", Rgb{1, 2, 3});
  EXPECT_EQ(pixel(r.image(), 48, 28), (Rgb{1, 2, 3}));
}

TEST(TopDownRenderer, ScanHitPointsLandWhereTheRangesSay) {
  RenderStyle s = plain_style();
  TopDownRenderer r(free_grid(), s);
  r.begin();
  // The sensor at the centre of pixel (48, 28): world (1 + 0.5/40, 0.5 - 0.5/40), facing +x.
  const Pose2 sensor{1.0125, 0.4875, 0.0};
  const std::vector<float> angles{0.0f, static_cast<float>(kPi / 2)};
  const std::vector<float> ranges{0.25f, std::numeric_limits<float>::infinity()};
  r.draw_scan(sensor, angles, ranges, 0.3);
  const cv::Mat& im = r.image();
  EXPECT_EQ(pixel(im, 58, 28), (Rgb{255, 0, 0}));           // hit: 0.25 m = 10 px to the right
  EXPECT_TRUE(near(pixel(im, 53, 28), {0, 255, 0}, 30));     // on the hit ray
  EXPECT_TRUE(near(pixel(im, 48, 20), {0, 200, 200}, 30));   // on the miss ray: 0.3 m = 12 px up
  EXPECT_EQ(pixel(im, 48, 12), (Rgb{255, 255, 255}));       // beyond max_range
  EXPECT_EQ(pixel(im, 58, 34), (Rgb{255, 255, 255}));       // away from the rays

  s.draw_misses = false;
  TopDownRenderer quiet(free_grid(), s);
  quiet.draw_scan(sensor, angles, ranges, 0.3);
  EXPECT_EQ(pixel(quiet.image(), 48, 20), (Rgb{255, 255, 255}));
  EXPECT_EQ(pixel(quiet.image(), 58, 28), (Rgb{255, 0, 0}));

  EXPECT_THROW(r.draw_scan(sensor, angles, std::vector<float>{1.0f}, 0.3), Error);
}

TEST(TopDownRenderer, ScanTurnsWithTheSensorHeading) {
  TopDownRenderer r(free_grid(), plain_style());
  // Facing +y, a ray at -90° points along +x again.
  r.draw_scan({1.0125, 0.4875, kPi / 2}, std::vector<float>{static_cast<float>(-kPi / 2)}, std::vector<float>{0.5f});
  EXPECT_EQ(pixel(r.image(), 68, 28), (Rgb{255, 0, 0}));
}

TEST(TopDownRenderer, BeliefIsBlendedOverTheMap) {
  TopDownRenderer r(free_grid(), plain_style());
  std::vector<std::int8_t> belief(200, kUnknown);
  belief[0] = kOccupied;
  r.draw_belief(belief);
  const cv::Mat& im = r.image();
  // Alpha 0.5 = 128/256 of (0, 0, 255) over white: (255·128) >> 8 = 127, blue stays 255.
  EXPECT_EQ(pixel(im, 10, 46), (Rgb{127, 127, 255}));
  EXPECT_EQ(pixel(im, 14, 46), (Rgb{255, 255, 255}));  // unknown belief: the map shows
  EXPECT_THROW(r.draw_belief(std::vector<std::int8_t>(199, 0)), Error);
}

TEST(TopDownRenderer, PathAndMarker) {
  TopDownRenderer r(free_grid(), plain_style());
  // A path along y = 0.5 (pixel row boundary 28, 2 px thick: rows 27 and 28).
  const std::vector<cv::Point2d> path{{0.5, 0.5}, {1.5, 0.5}};
  r.draw_path(path);
  EXPECT_TRUE(near(pixel(r.image(), 40, 28), {0, 120, 0}, 20));
  r.begin();
  // A marker at (1.0, 0.25) facing up: a 4 px thick segment along x, 0.3 m = 12 px long.
  r.draw_marker(1.0, 0.25, kPi / 2, "kitchen", 3);
  EXPECT_TRUE(near(pixel(r.image(), 44, 38), {255, 128, 0}, 20));  // y = 38 is 0.25 m = 10 px above 48
  EXPECT_EQ(pixel(r.image(), 30, 38), (Rgb{255, 255, 255}));      // beyond its half length of 6 px
}

TEST(TopDownRenderer, LabelsStayOnTopOfRobotsAndRays) {
  RenderStyle s = plain_style();
  s.label = {0, 0, 0};
  s.antialias = false;
  TopDownRenderer r(free_grid(), s);
  // A marker label, then a large robot drawn over where it goes: the label's black text must
  // still show inside the robot's disc, because labels are drawn when the image is read.
  r.draw_marker(1.0, 0.25, kPi / 2, "kitchen", 3);
  r.draw_robot({1.3, 0.55, 0.0}, 0.35, 1, std::string_view(""));
  const cv::Mat& im = r.image();
  int black = 0;
  for (int y = 0; y < im.rows; ++y) {
    for (int x = 0; x < im.cols; ++x) black += pixel(im, x, y) == Rgb{0, 0, 0};
  }
  EXPECT_GT(black, 20);  // the text's strokes
}

TEST(TopDownRenderer, StartSquareAndLegend) {
  RenderStyle s = plain_style();
  s.antialias = false;
  s.pixels_per_cell = 20;  // 400 × 200 pixels of map: room for the legend
  TopDownRenderer r(free_grid(), s);
  // A start square in robot 2's colour ({200, 100, 0}) centred at (1.0, 0.5): pixel (208, 108),
  // half a side of max(4, 0.15 m) = 30 px.
  ASSERT_EQ(r.world_to_pixel(1.0, 0.5), cv::Point2d(208, 108));
  r.draw_start(1.0, 0.5, 2);
  const cv::Mat& im = r.image();
  EXPECT_EQ(pixel(im, 178, 108), (Rgb{200, 100, 0}));  // on its left side
  EXPECT_EQ(pixel(im, 208, 108), (Rgb{255, 255, 255}));  // hollow
  EXPECT_EQ(pixel(im, 170, 108), (Rgb{255, 255, 255}));  // outside
  // The legend: a box in the top-right corner with a swatch in robot 2's colour.
  r.begin();
  r.draw_legend({{2, "robot 2: kitchen"}});
  const cv::Mat& with = r.image();
  int swatch = 0;
  for (int y = 0; y < with.rows / 2; ++y) {
    for (int x = with.cols / 2; x < with.cols; ++x) swatch += pixel(with, x, y) == Rgb{200, 100, 0};
  }
  EXPECT_GT(swatch, 10);
  r.begin();
  EXPECT_EQ(pixel(r.image(), with.cols - 3, 4), (Rgb{0, 0, 255}));  // gone at the next frame
}

TEST(TopDownRenderer, TrajectoryIsDrawnAndFades) {
  RenderStyle s = plain_style();
  s.trajectory = {0, 0, 0};
  s.trajectory_fade = 10;
  s.trajectory_faint = 0.0;
  TopDownRenderer r(free_grid(), s);
  std::vector<cv::Point2d> pts;
  for (int i = 0; i <= 40; ++i) pts.push_back({0.2 + 0.04 * i, 0.5});  // 1.6 px per point
  r.draw_trajectory(pts);
  const cv::Mat& im = r.image();
  // The newest end is dark, the oldest as faint as the free colour.
  EXPECT_LT(pixel(im, 79, 28).r, 60);
  EXPECT_EQ(pixel(im, 20, 28), (Rgb{255, 255, 255}));
}

TEST(TopDownRenderer, CornerTextIsDrawnOnceOnTop) {
  TopDownRenderer r(free_grid(), plain_style());
  EXPECT_EQ(pixel(r.image(), 3, 3), (Rgb{0, 0, 255}));  // no text: nothing drawn
  r.begin({.frame = 3, .time = 0.3, .status = "ok"});
  const Rgb first = pixel(r.image(), 3, 3);
  EXPECT_TRUE(near(first, {0, 0, 128}, 1));  // half of the background's blue under a black box
  EXPECT_EQ(pixel(r.image(), 3, 3), first);  // asking again does not darken it twice
  r.begin();
  EXPECT_EQ(pixel(r.image(), 3, 3), (Rgb{0, 0, 255}));
}

TEST(TopDownRenderer, SkipsNonFiniteInput) {
  TopDownRenderer r(free_grid(), plain_style());
  const double nan = std::nan("");
  r.draw_robot({nan, 0.5, 0.0}, 0.2, 1);
  const std::vector<cv::Point2d> path{{0.5, 0.5}, {nan, nan}, {1.5, 0.5}};
  r.draw_path(path);
  r.draw_marker(nan, 0, 0, "x");
  EXPECT_EQ(pixel(r.image(), 48, 28), (Rgb{255, 255, 255}));  // the gap in the path
}

// ---------------------------------------------------------------- image sequences

TEST(ImageSequence, NumberedPngFiles) {
  TempDir dir;
  ImageSequence seq((dir.path() / "frames").string());
  for (int i = 0; i < 3; ++i) seq.write(solid_frame(20, 10, i));
  EXPECT_EQ(seq.frames(), 3);
  EXPECT_TRUE(fs::exists(dir / "frames/frame_00001.png"));
  EXPECT_TRUE(fs::exists(dir / "frames/frame_00003.png"));
  EXPECT_FALSE(fs::exists(dir / "frames/frame_00004.png"));
  const cv::Mat back = read_image(dir / "frames/frame_00002.png");
  EXPECT_EQ(pixel(back, 5, 5), (Rgb{60, 185, 90}));  // frame 1's colour, RGB order kept
  const std::string e = error_of([&] { seq.write(solid_frame(21, 10, 0)); });
  EXPECT_NE(e.find("frame_00004.png"), std::string::npos) << e;
}

// ---------------------------------------------------------------- the view's frame sink

namespace {

/// A sink that keeps what it is given (copies, as the interface asks) and counts close().
class RecordingSink final : public FrameSink {
 public:
  void write(const cv::Mat& rgb) override { frames.push_back(rgb.clone()); }
  void close() override { ++closed; }
  std::vector<cv::Mat> frames;
  int closed = 0;
};

std::shared_ptr<PhysicsWorld> one_robot_world() {
  const std::vector<RobotSettings> robots{RobotSettings{.id = 1, .start = {0.5, 0.5, 0.0}}};
  return std::make_shared<PhysicsWorld>(free_grid(), robots, PhysicsSettings{});
}

}  // namespace

TEST(SimViewSink, EveryFrameThenTheFinalStateHeldThenOneClose) {
  auto sink = std::make_shared<RecordingSink>();
  SimView view(one_robot_world(), free_grid(), plain_style());
  view.record_video(sink);
  for (std::uint64_t t = 0; t < 4; ++t) {
    view.begin_frame({.frame = t, .time = 0.1 * static_cast<double>(t)});
    view.end_frame({.frame = t, .time = 0.1 * static_cast<double>(t)});
  }
  ASSERT_EQ(sink->frames.size(), 4u);
  EXPECT_EQ(sink->closed, 0);
  view.finish(3);  // the last frame drawn again, three times, then closed
  ASSERT_EQ(sink->frames.size(), 7u);
  EXPECT_EQ(sink->closed, 1);
  const cv::Size size = view.renderer().size();
  for (const cv::Mat& f : sink->frames) {
    EXPECT_EQ(f.size(), size);
    EXPECT_EQ(f.type(), CV_8UC3);
  }
  EXPECT_EQ(cv::norm(sink->frames[4], sink->frames[6], cv::NORM_INF), 0.0);  // the held frames are one picture
  EXPECT_EQ(view.frames_written(), 5);  // four frames and the held one
  // Finished: later frames reach no sink, and closing again does nothing.
  view.begin_frame({.frame = 4, .time = 0.4});
  view.end_frame({.frame = 4, .time = 0.4});
  view.close();
  EXPECT_EQ(sink->frames.size(), 7u);
  EXPECT_EQ(sink->closed, 1);
}

TEST(SimViewSink, ASinkGivenNoFramesIsNotClosedAndNothingIsDrawnWithoutOne) {
  auto sink = std::make_shared<RecordingSink>();
  {
    SimView view(one_robot_world(), free_grid(), plain_style());
    view.record_video(sink);
  }  // destroyed before any frame: nothing to finish
  EXPECT_EQ(sink->closed, 0);
  SimView view(one_robot_world(), free_grid(), plain_style());
  view.begin_frame({.frame = 0});
  view.end_frame({.frame = 0});
  view.finish(5);
  EXPECT_EQ(view.frames_written(), 0);
  EXPECT_EQ(view.trajectories().at(1).size(), 1u);  // the trajectory is kept all the same
}

TEST(SimViewSink, DestroyingTheViewClosesItsSink) {
  auto sink = std::make_shared<RecordingSink>();
  {
    SimView view(one_robot_world(), free_grid(), plain_style());
    view.record_video(sink);
    view.begin_frame({.frame = 0});
    view.end_frame({.frame = 0});
  }
  EXPECT_EQ(sink->frames.size(), 1u);
  EXPECT_EQ(sink->closed, 1);
}
