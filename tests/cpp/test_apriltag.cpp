// AprilTag detection, pose and bitmaps (vwg/perception/apriltag.hpp). Expected values come from the
// data files in tests/data/apriltag/ (upstream's ground truth, apriltag-imgs bitmaps, the family's
// codes) or from hand geometry (tags drawn into images with a known pinhole projection).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vwg/error.hpp"
#include "vwg/perception/apriltag.hpp"

using namespace vwg;
using namespace vwg::perception;

namespace {

namespace fs = std::filesystem;

fs::path data_dir() {
  if (const char* env = std::getenv("VWG_APRILTAG_DATA")) return env;
  return fs::path(__FILE__).parent_path().parent_path() / "data" / "apriltag";
}

// --- upstream ground truth ------------------------------------------------------------------------

struct ExpectedTag {
  int id = 0;
  std::array<std::array<double, 2>, 4> corners{};
};

/// Lines "id, (x0 y0), (x1 y1), (x2 y2), (x3 y3)".
std::vector<ExpectedTag> read_ground_truth(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  std::vector<ExpectedTag> tags;
  std::string line;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string original = line;
    EXPECT_EQ(std::count(line.begin(), line.end(), '('), 4) << "bad line: " << original;
    for (char& ch : line) {
      if (ch == ',' || ch == '(' || ch == ')') ch = ' ';
    }
    std::istringstream fields(line);
    ExpectedTag t;
    fields >> t.id;
    for (auto& p : t.corners) fields >> p[0] >> p[1];
    std::string rest;
    EXPECT_TRUE(fields && !(fields >> rest)) << "bad line: " << original;
    tags.push_back(t);
  }
  return tags;
}

double corner_distance(const TagDetection& d, const ExpectedTag& e, double dx = 0.0, double dy = 0.0) {
  double worst = 0.0;
  for (int k = 0; k < 4; ++k) {
    worst = std::max(worst, std::hypot(d.corners[k][0] - (e.corners[k][0] + dx), d.corners[k][1] - (e.corners[k][1] + dy)));
  }
  return worst;
}

/// The detection of `found` with e's id closest to it (worst corner distance), or -1.
double best_match(const std::vector<TagDetection>& found, const ExpectedTag& e, double dx = 0.0, double dy = 0.0) {
  double best = -1.0;
  for (const auto& d : found) {
    if (d.id != e.id) continue;
    const double dist = corner_distance(d, e, dx, dy);
    if (best < 0 || dist < best) best = dist;
  }
  return best;
}

cv::Mat read_gray(const fs::path& path) {
  cv::Mat m = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(m.empty()) << path;
  return m;
}

std::vector<TagDetection> detect_mat(const AprilTagDetector& det, const cv::Mat& gray) {
  return det.detect(gray.data, gray.cols, gray.rows, static_cast<int>(gray.step));
}

AprilTagSettings upstream_test_settings() {
  AprilTagSettings s;  // the ground truth's settings: decimate 1, no edge refinement, the rest default
  s.quad_decimate = 1.0;
  s.refine_edges = false;
  return s;
}

const char* const kGroundTruth[] = {"33369213973_9d9bb4cc96_c", "34085369442_304b6bafd9_c"};

// --- bitmaps ------------------------------------------------------------------------------------

/// A 10×10 apriltag-imgs PNG as grey values (checked: opaque, R = G = B).
cv::Mat read_tag_png(const fs::path& path) {
  cv::Mat rgba = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(rgba.type(), CV_8UC4) << path;
  std::vector<cv::Mat> ch;
  cv::split(rgba, ch);
  EXPECT_EQ(cv::countNonZero(ch[3] != 255), 0) << path << ": not opaque";
  EXPECT_EQ(cv::countNonZero(ch[0] != ch[1]), 0) << path;
  EXPECT_EQ(cv::countNonZero(ch[1] != ch[2]), 0) << path;
  return ch[0].clone();
}

cv::Mat as_mat(const GrayImage& img) {
  return cv::Mat(img.height, img.width, CV_8UC1, const_cast<std::uint8_t*>(img.pixels.data())).clone();
}

bool same_image(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::countNonZero(a != b) == 0;
}

// --- synthetic camera -----------------------------------------------------------------------------

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 mul(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}

std::array<double, 2> apply(const Mat3& h, double x, double y) {
  const double w = h[2][0] * x + h[2][1] * y + h[2][2];
  return {(h[0][0] * x + h[0][1] * y + h[0][2]) / w, (h[1][0] * x + h[1][1] * y + h[1][2]) / w};
}

/// Rotation by `yaw` about the camera's y axis (down): the tag turns about its vertical axis.
Mat3 rot_y(double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return Mat3{{{c, 0, s}, {0, 1, 0}, {-s, 0, c}}};
}

struct Scene {
  int width = 640, height = 480;
  CameraIntrinsics camera{600.0, 600.0, 320.0, 240.0};  // pixel centres at +0.5: (320, 240) is the image centre
  double tag_size = 0.2;    // side of the black square, metres (8 of tag36h11's 10 cells)
  int background = 170;     // a grey wall around the tag's white ring
};

/// Homography from bitmap coordinates of a 10-cell tag36h11 bitmap (cell j covers [j, j+1), the
/// tag centre at (5, 5)) to image pixels (pixel centres at +0.5), for a tag with rotation R (tag to
/// camera) and centre t (camera frame, metres): p = K [c·R₀, c·R₁, t − 5c(R₀ + R₁)] b, c = size / 8.
Mat3 tag_homography(const Scene& s, const Mat3& R, const std::array<double, 3>& t) {
  const double c = s.tag_size / 8.0;
  Mat3 M{};
  for (int i = 0; i < 3; ++i) {
    M[i][0] = c * R[i][0];
    M[i][1] = c * R[i][1];
    M[i][2] = t[i] - 5.0 * c * (R[i][0] + R[i][1]);
  }
  const Mat3 K{{{s.camera.fx, 0, s.camera.cx}, {0, s.camera.fy, s.camera.cy}, {0, 0, 1}}};
  return mul(K, M);
}

/// The camera image of the tag: drawn at 4× with nearest-cell sampling, then box-averaged to 1×.
cv::Mat render_scene(const Scene& s, int id, const Mat3& H) {
  constexpr int kSuper = 4;
  const GrayImage bitmap = render_tag("tag36h11", id);
  const cv::Mat src = as_mat(bitmap);
  // OpenCV puts pixel centres at integers: shift by half a pixel on both sides of the homography.
  const Mat3 to_cv{{{1, 0, -0.5}, {0, 1, -0.5}, {0, 0, 1}}};
  const Mat3 from_cv{{{1, 0, 0.5}, {0, 1, 0.5}, {0, 0, 1}}};
  const Mat3 up{{{kSuper, 0, 0}, {0, kSuper, 0}, {0, 0, 1}}};
  const Mat3 Hs = mul(to_cv, mul(up, mul(H, from_cv)));
  cv::Mat h(3, 3, CV_64F);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) h.at<double>(i, j) = Hs[i][j];
  cv::Mat big;
  cv::warpPerspective(src, big, h, cv::Size(s.width * kSuper, s.height * kSuper), cv::INTER_NEAREST,
                      cv::BORDER_CONSTANT, cv::Scalar(s.background));
  cv::Mat img;
  cv::resize(big, img, cv::Size(s.width, s.height), 0, 0, cv::INTER_AREA);
  return img;
}

double deg(double rad) { return rad * 180.0 / std::numbers::pi; }
double rad(double degrees) { return degrees * std::numbers::pi / 180.0; }

}  // namespace

// --- upstream's test images -----------------------------------------------------------------------

class GroundTruth : public ::testing::TestWithParam<const char*> {};

TEST_P(GroundTruth, EveryTagFoundWithCornersWithin2Px) {
  const fs::path dir = data_dir() / "test_data";
  const auto expected = read_ground_truth(dir / (std::string(GetParam()) + ".txt"));
  ASSERT_FALSE(expected.empty());
  const cv::Mat gray = read_gray(dir / (std::string(GetParam()) + ".jpg"));
  const AprilTagDetector det(upstream_test_settings());
  const auto found = detect_mat(det, gray);
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const double dist = best_match(found, expected[i]);
    EXPECT_GE(dist, 0.0) << "expected tag " << i << " (id " << expected[i].id << ") not found";
    EXPECT_LT(dist, 2.0) << "expected tag " << i << ": worst corner " << dist << " px away";
  }
  // The ground truth is the library's whole output on these images: nothing else either.
  EXPECT_EQ(found.size(), expected.size());
  for (const auto& d : found) {
    EXPECT_GE(d.hamming, 0);
    EXPECT_LE(d.hamming, 2);
    // The centre is inside the quad: between the corners' extremes.
    double lo = 1e9, hi = -1e9;
    for (const auto& p : d.corners) lo = std::min(lo, p[0]), hi = std::max(hi, p[0]);
    EXPECT_GT(d.center[0], lo);
    EXPECT_LT(d.center[0], hi);
  }
}

TEST_P(GroundTruth, DefaultSettingsFindOnlyTrueTags) {
  // Decimation 2 with edge refinement finds fewer tags, but each is one of the ground truth's.
  const fs::path dir = data_dir() / "test_data";
  const auto expected = read_ground_truth(dir / (std::string(GetParam()) + ".txt"));
  const cv::Mat gray = read_gray(dir / (std::string(GetParam()) + ".jpg"));
  const AprilTagDetector det;
  const auto found = detect_mat(det, gray);
  EXPECT_GT(found.size(), 0u);
  for (const auto& d : found) {
    double best = 1e9;
    for (const auto& e : expected) {
      if (e.id == d.id) best = std::min(best, corner_distance(d, e));
    }
    EXPECT_LT(best, 2.0) << "detection at (" << d.center[0] << ", " << d.center[1] << ") matches no true tag";
  }
}

TEST_P(GroundTruth, CropWithRowStrideShiftsTheCorners) {
  // A window of the image, passed as a pointer into the full image with the full row stride.
  const fs::path dir = data_dir() / "test_data";
  const auto expected = read_ground_truth(dir / (std::string(GetParam()) + ".txt"));
  const cv::Mat gray = read_gray(dir / (std::string(GetParam()) + ".jpg"));
  const int x0 = 200, y0 = 240, w = 400, h = 200;
  ASSERT_LE(x0 + w, gray.cols);
  ASSERT_LE(y0 + h, gray.rows);
  const AprilTagDetector det(upstream_test_settings());
  const auto found = det.detect(gray.ptr<std::uint8_t>(y0) + x0, w, h, static_cast<int>(gray.step));
  int inside = 0;
  for (const auto& e : expected) {
    bool in = true;
    for (const auto& p : e.corners) in = in && p[0] > x0 + 4 && p[0] < x0 + w - 4 && p[1] > y0 + 4 && p[1] < y0 + h - 4;
    if (!in) continue;
    ++inside;
    const double dist = best_match(found, e, -x0, -y0);
    EXPECT_GE(dist, 0.0);
    EXPECT_LT(dist, 2.0);
  }
  EXPECT_GT(inside, 3);
}

INSTANTIATE_TEST_SUITE_P(Upstream, GroundTruth, ::testing::ValuesIn(kGroundTruth));

// --- bitmaps ------------------------------------------------------------------------------------

TEST(AprilTagBitmap, EqualsTheApriltagImgsPngs) {
  const fs::path dir = data_dir() / "tag36h11_imgs";
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".png" || name.rfind("tag36_11_", 0) != 0) continue;
    const int id = std::stoi(name.substr(9, 5));
    const cv::Mat png = read_tag_png(entry.path());
    const GrayImage img = render_tag("tag36h11", id);
    EXPECT_EQ(img.width, 10);
    EXPECT_EQ(img.height, 10);
    EXPECT_TRUE(same_image(as_mat(img), png)) << name;
    // Scaled by 7 with a 3-pixel white border: each cell a 7×7 block, then the border.
    cv::Mat big;
    cv::resize(png, big, cv::Size(70, 70), 0, 0, cv::INTER_NEAREST);
    cv::copyMakeBorder(big, big, 3, 3, 3, 3, cv::BORDER_CONSTANT, cv::Scalar(255));
    EXPECT_TRUE(same_image(as_mat(render_tag("tag36h11", id, 3, 7)), big)) << name;
    ++checked;
  }
  EXPECT_EQ(checked, 7);
}

TEST(AprilTagBitmap, AllCodesFollowTheFamilyLayout) {
  // tag36h11_layout.txt: bit k (MSB first) of a code is the cell (bit_x[k]+1, bit_y[k]+1) of the
  // 10×10 bitmap, white = 1; the outer ring is white, the next ring black.
  std::ifstream layout(data_dir() / "tag36h11_layout.txt");
  ASSERT_TRUE(layout);
  std::vector<int> bx, by;
  std::string line;
  while (std::getline(layout, line)) {
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    int v;
    if (key == "bit_x") while (ss >> v) bx.push_back(v);
    if (key == "bit_y") while (ss >> v) by.push_back(v);
  }
  ASSERT_EQ(bx.size(), 36u);
  ASSERT_EQ(by.size(), 36u);
  std::ifstream codes(data_dir() / "tag36h11_codes.txt");
  ASSERT_TRUE(codes);
  int id = 0, n = 0;
  std::string hex;
  while (codes >> id >> hex) {
    const std::uint64_t code = std::stoull(hex, nullptr, 16);
    cv::Mat expected(10, 10, CV_8UC1, cv::Scalar(0));
    for (int i = 0; i < 10; ++i) {
      expected.at<std::uint8_t>(0, i) = expected.at<std::uint8_t>(9, i) = 255;
      expected.at<std::uint8_t>(i, 0) = expected.at<std::uint8_t>(i, 9) = 255;
    }
    for (int k = 0; k < 36; ++k) {
      if ((code >> (35 - k)) & 1u) expected.at<std::uint8_t>(by[k] + 1, bx[k] + 1) = 255;
    }
    EXPECT_TRUE(same_image(as_mat(render_tag("tag36h11", id)), expected)) << "id " << id;
    ++n;
  }
  EXPECT_EQ(n, 587);
  EXPECT_EQ(family_info("tag36h11").codes, 587);
}

TEST(AprilTagBitmap, FamilyInfo) {
  const TagFamilyInfo f = family_info("tag36h11");
  EXPECT_EQ(f.name, "tag36h11");
  EXPECT_EQ(f.bits, 36);
  EXPECT_EQ(f.min_hamming, 11);
  EXPECT_EQ(f.width_at_border, 8);
  EXPECT_EQ(f.total_width, 10);
  EXPECT_FALSE(f.reversed_border);
  const auto names = tag_families();
  EXPECT_NE(std::find(names.begin(), names.end(), "tag36h11"), names.end());
  for (const auto& name : names) {
    const TagFamilyInfo g = family_info(name);
    const GrayImage img = render_tag(name, g.codes - 1);
    EXPECT_EQ(img.width, g.total_width) << name;
  }
}

// --- detection of rendered tags -------------------------------------------------------------------

TEST(AprilTagDetect, UpscaledRenderedTagsAndTheCornerOrder) {
  // Cells of 10 px and a 20 px quiet zone: the black square spans pixels 30..110 (edges between
  // pixels; pixel centres at +0.5). Upright: p0 bottom-left, then bottom-right, top-right, top-left.
  const std::array<std::array<double, 2>, 4> upright{{{30, 110}, {110, 110}, {110, 30}, {30, 30}}};
  for (int id : {0, 1, 2, 5, 42, 100, 586}) {
    const GrayImage img = render_tag("tag36h11", id, 20, 10);
    ASSERT_EQ(img.width, 140);
    for (const AprilTagSettings& s : {AprilTagSettings{}, upstream_test_settings()}) {
      const auto found = AprilTagDetector(s).detect(img);
      ASSERT_EQ(found.size(), 1u) << "id " << id;
      EXPECT_EQ(found[0].id, id);
      EXPECT_EQ(found[0].hamming, 0);
      for (int k = 0; k < 4; ++k) {
        EXPECT_NEAR(found[0].corners[k][0], upright[k][0], 0.5) << "id " << id << " p" << k;
        EXPECT_NEAR(found[0].corners[k][1], upright[k][1], 0.5) << "id " << id << " p" << k;
      }
      EXPECT_NEAR(found[0].center[0], 70.0, 0.5);
      EXPECT_NEAR(found[0].center[1], 70.0, 0.5);
      // The homography takes tag (-1, 1) to p0 and (0, 0) to the centre.
      Mat3 H;
      for (int i = 0; i < 9; ++i) H[i / 3][i % 3] = found[0].homography[i];
      const auto p0 = apply(H, -1, 1), c = apply(H, 0, 0);
      EXPECT_NEAR(p0[0], 30, 0.5);
      EXPECT_NEAR(p0[1], 110, 0.5);
      EXPECT_NEAR(c[0], 70, 0.5);
      EXPECT_NEAR(c[1], 70, 0.5);
    }
  }
}

TEST(AprilTagDetect, CornerOrderFollowsTheTagWhenTheImageTurns) {
  // Turned 90° clockwise, a point (x, y) goes to (140 - y, x): the upright corners p0..p3 land at
  // (30, 30), (30, 110), (110, 110), (110, 30).
  const cv::Mat upright = as_mat(render_tag("tag36h11", 42, 20, 10));
  cv::Mat turned;
  cv::rotate(upright, turned, cv::ROTATE_90_CLOCKWISE);
  const auto found = detect_mat(AprilTagDetector(), turned);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 42);
  const std::array<std::array<double, 2>, 4> expected{{{30, 30}, {30, 110}, {110, 110}, {110, 30}}};
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(found[0].corners[k][0], expected[k][0], 0.5) << "p" << k;
    EXPECT_NEAR(found[0].corners[k][1], expected[k][1], 0.5) << "p" << k;
  }
}

TEST(AprilTagDetect, InputIsNeverModified) {
  // Without decimation the library blurs its quad image in place; the detector copies first.
  cv::Mat img = as_mat(render_tag("tag36h11", 5, 20, 10));
  const cv::Mat before = img.clone();
  for (double sigma : {0.0, 0.8, -0.8, 2.0}) {
    for (double decimate : {1.0, 2.0}) {
      AprilTagSettings s;
      s.quad_sigma = sigma;
      s.quad_decimate = decimate;
      const auto found = detect_mat(AprilTagDetector(s), img);
      EXPECT_TRUE(same_image(img, before)) << "sigma " << sigma << " decimate " << decimate;
      if (sigma == 0.0) {
        ASSERT_EQ(found.size(), 1u);
        EXPECT_EQ(found[0].id, 5);
      }
    }
  }
}

TEST(AprilTagDetect, OtherFamilies) {
  for (const char* family : {"tag25h9", "tag16h5", "tagStandard41h12"}) {
    const GrayImage img = render_tag(family, 3, 30, 12);
    AprilTagSettings s;
    s.family = family;
    const auto found = AprilTagDetector(s).detect(img);
    ASSERT_EQ(found.size(), 1u) << family;
    EXPECT_EQ(found[0].id, 3) << family;
  }
}

TEST(AprilTagDetect, SeveralThreadsShareOneDetector) {
  const fs::path dir = data_dir() / "test_data";
  const auto expected = read_ground_truth(dir / (std::string(kGroundTruth[1]) + ".txt"));
  const cv::Mat gray = read_gray(dir / (std::string(kGroundTruth[1]) + ".jpg"));
  const AprilTagDetector det(upstream_test_settings());
  std::atomic<int> bad{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 3; ++i) {
        const auto found = detect_mat(det, gray);
        if (found.size() != expected.size()) ++bad;
        for (const auto& e : expected) {
          const double d = best_match(found, e);
          if (d < 0 || d >= 2.0) ++bad;
        }
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(bad.load(), 0);
}

TEST(AprilTagDetect, LibraryWorkerThreadsAndMoves) {
  AprilTagSettings s = upstream_test_settings();
  s.threads = 2;
  AprilTagDetector a(s);
  AprilTagDetector b(std::move(a));
  const fs::path dir = data_dir() / "test_data";
  const auto expected = read_ground_truth(dir / (std::string(kGroundTruth[0]) + ".txt"));
  const auto found = detect_mat(b, read_gray(dir / (std::string(kGroundTruth[0]) + ".jpg")));
  EXPECT_EQ(found.size(), expected.size());
  EXPECT_EQ(b.settings().threads, 2);
}

TEST(AprilTagDetect, TinyAndNoisyImagesDoNotCrash) {
  std::mt19937 rng(7);
  for (double decimate : {1.0, 1.5, 2.0, 4.0}) {
    AprilTagSettings s;
    s.quad_decimate = decimate;
    const AprilTagDetector det(s);
    for (int w = 1; w <= 24; ++w) {
      for (int h = 1; h <= 24; h += 5) {
        std::vector<std::uint8_t> img(static_cast<std::size_t>(w) * h);
        for (auto& v : img) v = static_cast<std::uint8_t>(rng());
        const auto found = det.detect(img.data(), w, h, w);
        if (w < 6 || h < 6) {
          EXPECT_TRUE(found.empty());
        }
        std::fill(img.begin(), img.end(), std::uint8_t{0});
        EXPECT_TRUE(det.detect(img.data(), w, h, w).empty());
      }
    }
  }
}

// --- pose -----------------------------------------------------------------------------------------

struct PoseCase {
  double range;    // horizontal distance, metres
  double bearing;  // degrees, positive to the left
  double height;   // tag centre below (+) / above (-) the optical axis, metres
  double yaw;      // the tag turned about its vertical axis, degrees
};

// Readable test names in ctest and gtest output (gtest prints raw bytes otherwise).
void PrintTo(const PoseCase& c, std::ostream* os) {
  *os << "range " << c.range << " m, bearing " << c.bearing << " deg, height " << c.height << " m, yaw " << c.yaw
      << " deg";
}

class SyntheticPose : public ::testing::TestWithParam<PoseCase> {};

TEST_P(SyntheticPose, DistanceWithin5PercentBearingWithin2Degrees) {
  const PoseCase pc = GetParam();
  const Scene scene;
  const double b = rad(pc.bearing);
  // Camera frame: x right, y down, z forward; to the left is -x.
  const std::array<double, 3> t{-pc.range * std::sin(b), pc.height, pc.range * std::cos(b)};
  const Mat3 R = rot_y(rad(pc.yaw));
  const Mat3 H = tag_homography(scene, R, t);
  // The black square's corners p0..p3 are the bitmap points (1, 9), (9, 9), (9, 1), (1, 1).
  const std::array<std::array<double, 2>, 4> cells{{{1, 9}, {9, 9}, {9, 1}, {1, 1}}};
  std::array<std::array<double, 2>, 4> corners;
  for (int k = 0; k < 4; ++k) {
    corners[k] = apply(H, cells[k][0], cells[k][1]);
    ASSERT_GT(corners[k][0], 2);
    ASSERT_LT(corners[k][0], scene.width - 2);
    ASSERT_GT(corners[k][1], 2);
    ASSERT_LT(corners[k][1], scene.height - 2);
  }
  const cv::Mat img = render_scene(scene, 7, H);
  const auto found = detect_mat(AprilTagDetector(), img);
  ASSERT_EQ(found.size(), 1u);
  const TagDetection& d = found[0];
  EXPECT_EQ(d.id, 7);
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT(std::hypot(d.corners[k][0] - corners[k][0], d.corners[k][1] - corners[k][1]), 1.0) << "p" << k;
  }

  const TagPose pose = estimate_pose(d, scene.tag_size, scene.camera);
  const double distance = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
  const double bearing = std::atan2(-t[0], t[2]);
  EXPECT_LT(std::fabs(pose.distance - distance) / distance, 0.05) << pose.distance << " vs " << distance;
  EXPECT_LT(std::fabs(deg(pose.bearing - bearing)), 2.0) << deg(pose.bearing) << " vs " << deg(bearing);
  EXPECT_NEAR(pose.distance,
              std::sqrt(pose.translation[0] * pose.translation[0] + pose.translation[1] * pose.translation[1] +
                        pose.translation[2] * pose.translation[2]),
              1e-12);
  EXPECT_GE(pose.error, 0.0);
  // The rotation is a rotation, and near the tag's up to 2 m. Farther, a tag of 30 px or less
  // leaves the planar pose ambiguous (two minima, the flip about the line of sight): not checked.
  double trace = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double dot = 0.0;
      for (int k = 0; k < 3; ++k) dot += pose.rotation[3 * i + k] * pose.rotation[3 * j + k];
      EXPECT_NEAR(dot, i == j ? 1.0 : 0.0, 1e-6);
      trace += pose.rotation[3 * i + j] * R[i][j];
    }
  }
  const double angle = deg(std::acos(std::clamp((trace - 1.0) / 2.0, -1.0, 1.0)));
  if (pc.range <= 2.0) {
    EXPECT_LT(angle, 5.0) << "rotation off by " << angle << "°";
  }
  if (std::getenv("VWG_APRILTAG_VERBOSE")) {
    std::printf("range %.1f bearing %+.0f yaw %+.0f: distance err %.2f%%, bearing err %.3f°, rotation err %.1f°\n",
                pc.range, pc.bearing, pc.yaw, 100 * (pose.distance - distance) / distance,
                deg(pose.bearing - bearing), angle);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, SyntheticPose,
    ::testing::Values(PoseCase{0.5, 0, 0, 0}, PoseCase{0.5, 8, 0, 0}, PoseCase{0.5, -8, 0.05, 20},
                      PoseCase{1.0, 0, 0, 0}, PoseCase{1.0, 15, 0, -30}, PoseCase{1.0, -20, -0.1, 0},
                      PoseCase{2.0, 0, 0, 45}, PoseCase{2.0, 20, 0.2, 0}, PoseCase{2.0, -22, 0, 20},
                      PoseCase{3.5, 10, 0, -20}, PoseCase{3.5, -15, 0.3, 0}, PoseCase{5.0, 0, 0, 0},
                      PoseCase{5.0, 18, 0, 0}, PoseCase{5.0, -20, -0.3, 15}));

TEST(AprilTagPose, BearingSignAndDistanceByHand) {
  // A tag 2 m ahead and 0.5 m to the left, facing the camera: bearing atan2(0.5, 2) (positive).
  const Scene scene;
  const std::array<double, 3> t{-0.5, 0.0, 2.0};
  const cv::Mat img = render_scene(scene, 1, tag_homography(scene, rot_y(0.0), t));
  const auto found = detect_mat(AprilTagDetector(), img);
  ASSERT_EQ(found.size(), 1u);
  const TagPose pose = estimate_pose(found[0], scene.tag_size, scene.camera);
  EXPECT_NEAR(pose.bearing, std::atan2(0.5, 2.0), rad(2.0));
  EXPECT_GT(pose.bearing, 0.0);
  EXPECT_NEAR(pose.translation[0], -0.5, 0.05);
  EXPECT_NEAR(pose.translation[2], 2.0, 0.1);
  EXPECT_NEAR(pose.distance, std::hypot(0.5, 2.0), 0.05 * std::hypot(0.5, 2.0));
}

// --- errors ---------------------------------------------------------------------------------------

TEST(AprilTagErrors, BadImagesAndSettings) {
  const AprilTagDetector det;
  std::vector<std::uint8_t> px(100, 0);
  EXPECT_THROW(det.detect(nullptr, 10, 10, 10), SchemaError);
  EXPECT_THROW(det.detect(px.data(), 0, 10, 10), SchemaError);
  EXPECT_THROW(det.detect(px.data(), 10, 0, 10), SchemaError);
  EXPECT_THROW(det.detect(px.data(), -5, 10, 10), SchemaError);
  EXPECT_THROW(det.detect(px.data(), 10, 10, 9), SchemaError);
  EXPECT_THROW(det.detect(GrayImage{}), SchemaError);
  EXPECT_THROW(det.detect(GrayImage{10, 10, std::vector<std::uint8_t>(99)}), SchemaError);

  auto with = [](auto change) {
    AprilTagSettings s;
    change(s);
    return s;
  };
  EXPECT_THROW(AprilTagDetector(with([](auto& s) { s.family = "tag99h1"; })), SchemaError);
  EXPECT_THROW(AprilTagDetector(with([](auto& s) { s.quad_decimate = 2.5; })), SchemaError);
  EXPECT_THROW(AprilTagDetector(with([](auto& s) { s.quad_decimate = 0.5; })), SchemaError);
  EXPECT_THROW(AprilTagDetector(with([](auto& s) { s.quad_decimate = std::nan(""); })), SchemaError);
  EXPECT_THROW(AprilTagDetector(with([](auto& s) { s.quad_sigma = INFINITY; })), SchemaError);
  EXPECT_THROW(AprilTagDetector(with([](auto& s) { s.decode_sharpening = -1; })), SchemaError);
  EXPECT_THROW(AprilTagDetector(with([](auto& s) { s.threads = 0; })), SchemaError);
  EXPECT_THROW(AprilTagDetector(with([](auto& s) { s.max_hamming = 3; })), SchemaError);
  try {
    AprilTagDetector(with([](auto& s) { s.family = "tag36h12"; }));
    FAIL();
  } catch (const SchemaError& e) {
    EXPECT_EQ(e.field(), "family");
    EXPECT_NE(std::string(e.what()).find("tag36h11"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(AprilTagDetector(with([](auto& s) { s.quad_decimate = 1.5; })));
  EXPECT_NO_THROW(AprilTagDetector(with([](auto& s) { s.quad_decimate = 3.0; })));
}

TEST(AprilTagErrors, BadBitmapsAndPoses) {
  EXPECT_THROW(render_tag("tag36h11", -1), SchemaError);
  EXPECT_THROW(render_tag("tag36h11", 587), SchemaError);
  EXPECT_THROW(render_tag("nope", 0), SchemaError);
  EXPECT_THROW(render_tag("tag36h11", 0, -1), SchemaError);
  EXPECT_THROW(render_tag("tag36h11", 0, 0, 0), SchemaError);
  EXPECT_THROW(family_info("nope"), SchemaError);

  const auto found = AprilTagDetector().detect(render_tag("tag36h11", 0, 20, 10));
  ASSERT_EQ(found.size(), 1u);
  const CameraIntrinsics cam{500, 500, 70, 70};
  EXPECT_NO_THROW(estimate_pose(found[0], 0.1, cam));
  EXPECT_THROW(estimate_pose(found[0], 0.0, cam), SchemaError);
  EXPECT_THROW(estimate_pose(found[0], -0.1, cam), SchemaError);
  EXPECT_THROW(estimate_pose(found[0], 0.1, CameraIntrinsics{0, 500, 70, 70}), SchemaError);
  EXPECT_THROW(estimate_pose(found[0], 0.1, CameraIntrinsics{500, 500, NAN, 70}), SchemaError);
  TagDetection flat = found[0];
  for (auto& p : flat.corners) p = {10.0, 10.0};
  EXPECT_THROW(estimate_pose(flat, 0.1, cam), SchemaError);
  TagDetection singular = found[0];
  singular.homography.fill(0.0);
  EXPECT_THROW(estimate_pose(singular, 0.1, cam), SchemaError);
}
