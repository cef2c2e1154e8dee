#include "vwg/sim/camera.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include <opencv2/imgproc.hpp>

#include "vwg/error.hpp"
#include "vwg/sim/raycast.hpp"
#include "vwg/sim/render2d.hpp"
#include "vwg/sim/view3d.hpp"

namespace vwg::sim {

namespace {

constexpr const char* kFamily = "tag36h11";

/// A colour as the bytes of one pixel of the output format.
template <int Channels>
struct Pixel {
  std::array<std::uint8_t, Channels> v{};
  static Pixel of(Colour c) {
    Pixel p;
    if constexpr (Channels == 3) {
      p.v = {to_byte(c.r), to_byte(c.g), to_byte(c.b)};
    } else {
      p.v = {to_byte(luma(c))};
    }
    return p;
  }
  void store(std::uint8_t* dst) const { std::memcpy(dst, v.data(), Channels); }
};

/// dst = dst·(1 - w) + p·w, per channel (w in [0, 1]).
template <int Channels>
void blend(std::uint8_t* dst, const Pixel<Channels>& p, double w) {
  for (int c = 0; c < Channels; ++c) {
    dst[c] = static_cast<std::uint8_t>(dst[c] + (static_cast<int>(p.v[c]) - dst[c]) * w + 0.5);
  }
}

// --- the look of the world: a fixed light, a haze with distance ---------------------------------

/// Horizontal direction towards the light, from the east-north-east (30°): walls facing east are
/// brightest, west darkest, north and south in between, so corners read clearly.
constexpr double kLightAngle = std::numbers::pi / 6;
const double kLightX = std::cos(kLightAngle), kLightY = std::sin(kLightAngle);

const Colour kWall{222, 216, 204};
const Colour kFloor{96, 103, 112};
const Colour kCeiling{236, 236, 240};
const Colour kHaze{150, 152, 158};
const Colour kPaper{246, 246, 242};  // the tag's white cells
const Colour kInk{20, 20, 22};       // its black cells
constexpr double kHazeDistance = 40.0;  // metres at which 1/e of the surface colour is left

/// Half-Lambert shading of a vertical surface with horizontal normal (nx, ny): never fully dark, so
/// a wall turned away from the light still shows its markers.
float lambert(double nx, double ny) { return half_lambert(nx * kLightX + ny * kLightY, 0.64, 0.36); }
/// A surface's colour, shaded, seen through the haze at depth z.
Colour seen(Colour surface, float shade, double z) { return mix(kHaze, surface * shade, clarity(z, kHazeDistance)); }

/// A marker pixel that straddles a cell edge is the mean of kSub × kSub rays: edges land within
/// 1/16 px on average, well under the detector's own corner error.
constexpr std::size_t kSub = 8;
constexpr int kSamples = static_cast<int>(kSub * kSub);

/// floor(v) as an int within [lo, hi]; clamped first, since a wall or robot a hair from the camera
/// projects to rows far beyond int's range.
int floor_within(double v, int lo, int hi) { return static_cast<int>(std::floor(std::clamp(v, lo - 1.0, hi + 1.0))); }

/// Fraction of pixel row v (covering [v - 0.5, v + 0.5]) inside [top, bottom].
double coverage(int v, double top, double bottom) {
  return std::max(0.0, std::min(v + 0.5, bottom) - std::max(v - 0.5, top));
}

}  // namespace

// --- spec ---------------------------------------------------------------------------------------

double CameraSpec::fx() const { return PinholeCamera::focal_for(width, hfov); }

void check_settings(const CameraSpec& s, const std::string& owner) {
  if (s.width < 1 || s.width > 8192) throw SchemaError(owner + ".width", "expected 1 to 8192 pixels, got " + std::to_string(s.width));
  if (s.height < 1 || s.height > 8192) throw SchemaError(owner + ".height", "expected 1 to 8192 pixels, got " + std::to_string(s.height));
  if (!std::isfinite(s.hfov) || s.hfov <= 0 || s.hfov >= std::numbers::pi) throw SchemaError(owner + ".hfov", "expected a field of view in (0, π) radians");
  if (!std::isfinite(s.mount_height) || s.mount_height <= 0) throw SchemaError(owner + ".mount_height", "expected a finite height > 0, metres");
  if (!std::isfinite(s.wall_height) || s.wall_height <= s.mount_height) {
    throw SchemaError(owner + ".wall_height", "expected a finite height above the camera's mount_height");
  }
  if (!std::isfinite(s.robot_height) || s.robot_height <= 0) throw SchemaError(owner + ".robot_height", "expected a finite height > 0, metres");
  if (!std::isfinite(s.noise) || s.noise < 0) throw SchemaError(owner + ".noise", "expected a finite standard deviation >= 0, grey levels");
  if (!std::isfinite(s.blur) || s.blur < 0 || s.blur > 100) throw SchemaError(owner + ".blur", "expected a Gaussian sigma of 0 to 100 pixels");
  if (s.period < 1 || s.period > 1000000) {
    throw SchemaError(owner + ".period", "expected 1 to 1000000 frames between looks, got " + std::to_string(s.period));
  }
}

perception::CameraIntrinsics apriltag_intrinsics(const CameraSpec& s) {
  return {s.fx(), s.fy(), s.cx() + 0.5, s.cy() + 0.5};
}

void check_markers(std::span<const WallMarker> markers, double wall_height) {
  const int codes = perception::family_info(kFamily).codes;
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const WallMarker& m = markers[i];
    const std::string where = "markers[" + std::to_string(i) + "]";
    if (m.id < 0 || m.id >= codes) {
      throw SchemaError(where + ".id", "expected a tag36h11 id 0.." + std::to_string(codes - 1) + ", got " + std::to_string(m.id));
    }
    if (!std::isfinite(m.x) || !std::isfinite(m.y)) throw SchemaError(where + ".at", "expected a finite position, metres");
    if (!std::isfinite(m.facing)) throw SchemaError(where + ".facing", "expected a finite angle, radians");
    if (!std::isfinite(m.size) || m.size <= 0) throw SchemaError(where + ".size", "expected a finite size > 0, metres");
    if (!std::isfinite(m.height) || m.height <= 0 || m.height >= wall_height) {
      throw SchemaError(where + ".height", "expected the centre between the floor and the wall top (0, " + std::to_string(wall_height) + ") metres");
    }
  }
}

// --- the scene ----------------------------------------------------------------------------------

/// What does not change between frames: the raycaster, smoothed wall normals, the markers in the
/// form the sampler wants, the per-column ray geometry and the background column.
struct CameraRenderer::Scene {
  /// A marker ready to sample: its plane, axes and bitmap.
  struct Tag {
    double mx, my;            // centre on the wall
    double nx, ny;            // outward normal
    double rx, ry;            // along the wall, to the right of someone facing the marker
    double half;              // half the drawn square (bitmap with its white ring), metres
    double top;               // height of the drawn square's top edge
    double cells_per_metre;   // bitmap cells per metre on the wall
    int cells;                // bitmap cells across (10 for tag36h11)
    std::vector<std::uint8_t> black;  // cells × cells, row 0 at the top: 1 = black
    float shade;              // lambert() of its normal
  };

  GridRaycaster raycaster;
  OccupancyGrid geometry;  // size, resolution and origin only (no cells)
  std::vector<float> normal_x, normal_y;  // per cell: outward normal of the nearby walls, world frame
  std::vector<Tag> tags;
  double plane_tolerance;  // how far a wall hit may be from a marker's plane and still carry it
  RenderStyle style;  // the bodies' colours

  // Per image column u: the ray's direction relative to the heading, x_c = (u - cx) / fx, and the
  // horizontal distance per unit depth.
  std::vector<double> angles, column_x, stretch;
  std::vector<float> ranges;  // scratch: the scan of a frame
  std::vector<Colour> background;  // per row: the ceiling above the horizon, the floor below

  Scene(const OccupancyGrid& grid, int threshold) : raycaster(grid, threshold) {
    geometry.width = grid.width;
    geometry.height = grid.height;
    geometry.resolution = grid.resolution;
    geometry.origin = grid.origin;
    plane_tolerance = 2.0 * grid.resolution;
    compute_normals(grid, threshold);
  }

  /// Normals from the gradient of the blurred occupancy (sigma 1.5 cells): along a straight wall
  /// the face's normal, along a slanted wall drawn as a staircase of cells the wall's direction.
  void compute_normals(const OccupancyGrid& grid, int threshold) {
    cv::Mat occupied(grid.height, grid.width, CV_32F);
    for (int r = 0; r < grid.height; ++r) {
      float* row = occupied.ptr<float>(r);
      for (int c = 0; c < grid.width; ++c) row[c] = grid.blocked(r, c, threshold) ? 1.0f : 0.0f;
    }
    cv::GaussianBlur(occupied, occupied, cv::Size(0, 0), 1.5, 1.5, cv::BORDER_CONSTANT);
    cv::Mat gu, gv;
    cv::Sobel(occupied, gu, CV_32F, 1, 0, 3, 1.0, 0.0, cv::BORDER_CONSTANT);
    cv::Sobel(occupied, gv, CV_32F, 0, 1, 3, 1.0, 0.0, cv::BORDER_CONSTANT);
    const auto cells = static_cast<std::size_t>(grid.width) * grid.height;
    normal_x.assign(cells, 0.0f);
    normal_y.assign(cells, 0.0f);
    const double c = std::cos(grid.origin.theta), s = std::sin(grid.origin.theta);
    for (int r = 0; r < grid.height; ++r) {
      const float* du = gu.ptr<float>(r);
      const float* dv = gv.ptr<float>(r);
      for (int k = 0; k < grid.width; ++k) {
        const double len = std::hypot(du[k], dv[k]);
        if (len < 1e-3) continue;  // far from walls (or inside one): no direction
        const double nu = -du[k] / len, nv = -dv[k] / len;  // grid axes, pointing out of the walls
        const std::size_t i = static_cast<std::size_t>(r) * grid.width + k;
        normal_x[i] = static_cast<float>(c * nu - s * nv);
        normal_y[i] = static_cast<float>(s * nu + c * nv);
      }
    }
  }

  /// The normal of the wall a ray of direction (dx, dy) hit at (x, y): looked up a quarter cell in
  /// front of the hit, in the free cell the ray came from; facing the ray when there is none.
  void wall_normal(double x, double y, double dx, double dy, double& nx, double& ny) const {
    double u, v;
    geometry.world_to_grid(x - 0.25 * geometry.resolution * dx, y - 0.25 * geometry.resolution * dy, u, v);
    const int col = floor_within(u, -1, geometry.width), row = floor_within(v, -1, geometry.height);
    if (geometry.inside(row, col)) {
      const std::size_t i = static_cast<std::size_t>(row) * geometry.width + col;
      if (normal_x[i] != 0.0f || normal_y[i] != 0.0f) {
        nx = normal_x[i];
        ny = normal_y[i];
        return;
      }
    }
    nx = -dx;
    ny = -dy;
  }

  void set_markers(const std::vector<WallMarker>& markers) {
    const perception::TagFamilyInfo family = perception::family_info(kFamily);
    for (const WallMarker& m : markers) {
      Tag t;
      t.mx = m.x;
      t.my = m.y;
      t.nx = std::cos(m.facing);
      t.ny = std::sin(m.facing);
      t.rx = -t.ny;  // facing the marker one looks along -n; the right hand is -n turned clockwise
      t.ry = t.nx;
      t.cells = family.total_width;
      const double drawn = m.size * family.total_width / family.width_at_border;
      t.half = drawn / 2;
      t.top = m.height + t.half;
      t.cells_per_metre = t.cells / drawn;
      const perception::GrayImage bitmap = perception::render_tag(kFamily, m.id, 0, 1);
      t.black.resize(bitmap.pixels.size());
      for (std::size_t i = 0; i < bitmap.pixels.size(); ++i) t.black[i] = bitmap.pixels[i] < 128 ? 1 : 0;
      t.shade = lambert(t.nx, t.ny);
      tags.push_back(std::move(t));
    }
  }

  void set_spec(const CameraSpec& spec) {
    const auto w = static_cast<std::size_t>(spec.width);
    const double fx = spec.fx(), cx = spec.cx(), cy = spec.cy();
    angles.resize(w);
    column_x.resize(w);
    stretch.resize(w);
    ranges.resize(w);
    for (std::size_t u = 0; u < w; ++u) {
      column_x[u] = (static_cast<double>(u) - cx) / fx;
      angles[u] = std::atan((cx - static_cast<double>(u)) / fx);
      stretch[u] = std::sqrt(1.0 + column_x[u] * column_x[u]);
    }
    // Floor and ceiling: their depth depends on the row alone (the camera is level).
    background.resize(static_cast<std::size_t>(spec.height));
    for (int v = 0; v < spec.height; ++v) {
      const double down = (v - cy) / spec.fy();
      Colour c;
      if (down > 0) {
        c = seen(kFloor, 1.0f, spec.mount_height / down);
      } else if (down < 0) {
        c = seen(kCeiling, 1.0f, (spec.wall_height - spec.mount_height) / -down);
      } else {
        c = kHaze;
      }
      background[static_cast<std::size_t>(v)] = c;
    }
  }
};

// --- the renderer -------------------------------------------------------------------------------

CameraRenderer::CameraRenderer(const OccupancyGrid& grid, std::vector<WallMarker> markers, CameraSpec spec,
                               int threshold, std::uint64_t seed)
    : spec_(spec), markers_(std::move(markers)), rng_(seed) {
  check_settings(spec_, "camera");
  check_markers(markers_, spec_.wall_height);
  if (grid.width <= 0 || grid.height <= 0 || grid.data.size() != static_cast<std::size_t>(grid.width) * grid.height) {
    throw SchemaError("grid", "expected width × height cells");
  }
  if (!std::isfinite(grid.resolution) || grid.resolution <= 0) throw SchemaError("grid.resolution", "expected a finite value > 0");
  scene_ = std::make_unique<Scene>(grid, threshold);
  scene_->set_markers(markers_);
  scene_->set_spec(spec_);
}

CameraRenderer::~CameraRenderer() = default;
CameraRenderer::CameraRenderer(CameraRenderer&&) noexcept = default;
CameraRenderer& CameraRenderer::operator=(CameraRenderer&&) noexcept = default;

cv::Mat CameraRenderer::render(const Pose2& pose, std::span<const RobotShape> robots, PixelFormat format) {
  cv::Mat out;
  render(pose, robots, out, format);
  return out;
}

void CameraRenderer::render(const Pose2& pose, std::span<const RobotShape> robots, cv::Mat& out, PixelFormat format) {
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.theta)) {
    throw SchemaError("pose", "expected finite x, y, yaw");
  }
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const RobotShape& r = robots[i];
    if (!std::isfinite(r.pose.x) || !std::isfinite(r.pose.y) || !std::isfinite(r.pose.theta)) {
      throw SchemaError("robots[" + std::to_string(i) + "].pose", "expected finite x, y, yaw");
    }
    if (!std::isfinite(r.radius) || r.radius <= 0) throw SchemaError("robots[" + std::to_string(i) + "].radius", "expected a finite radius > 0");
  }
  const int type = format == PixelFormat::Grey ? CV_8UC1 : CV_8UC3;
  columns_.create(spec_.width, spec_.height, type);
  if (format == PixelFormat::Grey) {
    render_columns<1>(pose, robots, columns_);
  } else {
    render_columns<3>(pose, robots, columns_);
  }
  out.create(spec_.height, spec_.width, type);
  cv::transpose(columns_, out);
  // The lens blurs what reaches the sensor; the sensor adds its noise after that.
  if (spec_.blur > 0) cv::GaussianBlur(out, out, cv::Size(0, 0), spec_.blur, spec_.blur, cv::BORDER_REPLICATE);
  if (spec_.noise > 0) {
    // Approximately normal noise: the sum of four 16-bit uniforms from one 64-bit draw (Irwin-Hall,
    // variance 1/3 before scaling) costs no log, root or cosine per pixel as Box-Muller would; its
    // tails stop at 3.46 sigma, which pixel noise does not miss.
    const double scale = spec_.noise * std::sqrt(3.0) / 65536.0;
    for (int v = 0; v < out.rows; ++v) {
      std::uint8_t* p = out.ptr<std::uint8_t>(v);
      const int n = out.cols * out.channels();
      for (int i = 0; i < n; ++i) {
        const std::uint64_t bits = rng_.next_u64();
        const double sum = static_cast<double>((bits & 0xFFFF) + ((bits >> 16) & 0xFFFF) + ((bits >> 32) & 0xFFFF) + (bits >> 48));
        const double value = p[i] + (sum - 2.0 * 65535.0) * scale;
        p[i] = static_cast<std::uint8_t>(std::clamp(value + 0.5, 0.0, 255.0));
      }
    }
  }
}

template <int Channels>
void CameraRenderer::render_columns(const Pose2& pose, std::span<const RobotShape> robots, cv::Mat& columns) {
  Scene& sc = *scene_;
  const int W = spec_.width, H = spec_.height;
  const double fx = spec_.fx(), fy = spec_.fy(), cx = spec_.cx(), cy = spec_.cy();
  const double mount = spec_.mount_height, wall_top = spec_.wall_height;
  const PinholeCamera cam = PinholeCamera::level(pose, mount, fx, cx, cy);
  // Unnormalised horizontal ray direction of image x-coordinate u' (not necessarily a pixel
  // centre): forward plus x_c times right, so its forward component is 1 and a distance t along it
  // is the depth.
  auto direction = [&](double u, double& dx, double& dy) {
    const Vec3 d = cam.forward + cam.right * cam.column_x(u);
    dx = d.x();
    dy = d.y();
  };

  sc.raycaster.scan(pose, sc.angles, std::numeric_limits<double>::infinity(), sc.ranges);

  std::vector<Pixel<Channels>> background(static_cast<std::size_t>(H));
  for (int v = 0; v < H; ++v) background[static_cast<std::size_t>(v)] = Pixel<Channels>::of(sc.background[static_cast<std::size_t>(v)]);

  // The markers the camera is in front of; the others cannot be seen.
  std::vector<const Scene::Tag*> facing;
  for (const auto& t : sc.tags) {
    if ((pose.x - t.mx) * t.nx + (pose.y - t.my) * t.ny > 0) facing.push_back(&t);
  }
  struct Hit {
    double t1, t2;  // horizontal distances where the ray enters and leaves the cylinder
    std::size_t robot;
  };
  std::vector<Hit> hits;
  hits.reserve(robots.size());

  for (int u = 0; u < W; ++u) {
    const auto uu = static_cast<std::size_t>(u);
    std::uint8_t* col = columns.ptr<std::uint8_t>(u);
    for (int v = 0; v < H; ++v) background[static_cast<std::size_t>(v)].store(col + v * Channels);
    const Vec3 azimuth = (cam.forward + cam.right * sc.column_x[uu]) / sc.stretch[uu];  // unit direction
    const double azimuth_x = azimuth.x(), azimuth_y = azimuth.y();
    const double dist = sc.ranges[uu];

    if (std::isfinite(dist)) {
      const double z = std::max(dist / sc.stretch[uu], 1e-6);  // depth of the wall
      const double top = cy - fy * (wall_top - mount) / z, bottom = cy + fy * mount / z;
      const double hx = pose.x + dist * azimuth_x, hy = pose.y + dist * azimuth_y;
      double nx, ny;
      sc.wall_normal(hx, hy, azimuth_x, azimuth_y, nx, ny);
      const auto wall = Pixel<Channels>::of(seen(kWall, lambert(nx, ny), z));
      const int first = std::max(0, floor_within(top + 0.5, 0, H));
      const int last = std::min(H - 1, floor_within(bottom + 0.5, 0, H));
      for (int v = first; v <= last; ++v) {
        const double w = coverage(v, top, bottom);
        if (w >= 1.0) {
          wall.store(col + v * Channels);
        } else if (w > 0) {
          blend(col + v * Channels, wall, w);  // the wall's top or foot: anti-aliased
        }
      }

      for (const Scene::Tag* tp : facing) {
        const Scene::Tag& t = *tp;
        // The wall here must carry the marker: the hit is (nearly) on its plane and the ray meets
        // the plane from the front.
        const double off_plane = (hx - t.mx) * t.nx + (hy - t.my) * t.ny;
        if (std::fabs(off_plane) > sc.plane_tolerance || azimuth_x * t.nx + azimuth_y * t.ny >= 0) continue;
        const double reach = (t.mx - pose.x) * t.nx + (t.my - pose.y) * t.ny;  // < 0: the camera is in front
        // Where the rays of x-coordinate u' meet the marker's plane: depth and position along it.
        auto on_plane = [&](double u_, double& depth, double& along) {
          double dx, dy;
          direction(u_, dx, dy);
          depth = reach / (dx * t.nx + dy * t.ny);
          along = (pose.x + depth * dx - t.mx) * t.rx + (pose.y + depth * dy - t.my) * t.ry;
        };
        double depth_l, along_l, depth_r, along_r;
        on_plane(u - 0.5, depth_l, along_l);
        on_plane(u + 0.5, depth_r, along_r);
        if (!(depth_l > 0 && depth_r > 0)) continue;  // a pixel edge parallel to or behind the plane
        if (std::max(along_l, along_r) < -t.half || std::min(along_l, along_r) > t.half) continue;
        // The sub-columns, each with its depth and position along the marker.
        std::array<double, kSub> sub_depth{}, sub_along{};
        for (std::size_t i = 0; i < kSub; ++i) on_plane(u + (i + 0.5) / kSub - 0.5, sub_depth[i], sub_along[i]);
        const double z_mid = 0.5 * (depth_l + depth_r);
        const auto paper = Pixel<Channels>::of(seen(kPaper, t.shade, z_mid));
        const auto ink = Pixel<Channels>::of(seen(kInk, t.shade, z_mid));
        const double cells = t.cells_per_metre;
        const int n = t.cells;
        // The bitmap cell at (along, height): its index, or -1 outside the drawn square.
        auto cell_at = [&](double along, double h) {
          const double cu = (along + t.half) * cells, cv = (t.top - h) * cells;
          if (!(cu >= 0 && cv >= 0 && cu < n && cv < n)) return -1;
          return static_cast<int>(cv) * n + static_cast<int>(cu);
        };
        auto height_at = [&](double depth, double v_) { return mount - depth * (v_ - cy) / fy; };
        // Rows the drawn square can reach in this column.
        const double bottom_h = t.top - 2 * t.half;
        double v_lo = H, v_hi = -1;
        for (double d : {depth_l, depth_r}) {
          for (double h : {t.top, bottom_h}) {
            const double v_ = cy + fy * (mount - h) / d;
            v_lo = std::min(v_lo, v_);
            v_hi = std::max(v_hi, v_);
          }
        }
        const int v0 = std::max({0, first, floor_within(v_lo - 0.5, 0, H)});
        const int v1 = std::min({H - 1, last, floor_within(v_hi + 1.5, 0, H)});
        for (int v = v0; v <= v1; ++v) {
          std::uint8_t* dst = col + v * Channels;
          // The pixel's footprint on the plane is a convex quad (a projected square); if its four
          // corners lie in one cell, so does all of it.
          const int c00 = cell_at(along_l, height_at(depth_l, v - 0.5));
          const int c01 = cell_at(along_l, height_at(depth_l, v + 0.5));
          const int c10 = cell_at(along_r, height_at(depth_r, v - 0.5));
          const int c11 = cell_at(along_r, height_at(depth_r, v + 0.5));
          if (c00 >= 0 && c00 == c01 && c00 == c10 && c00 == c11) {
            (t.black[static_cast<std::size_t>(c00)] ? ink : paper).store(dst);
            continue;
          }
          int n_ink = 0, n_paper = 0;
          for (std::size_t i = 0; i < kSub; ++i) {
            for (std::size_t j = 0; j < kSub; ++j) {
              const int c = cell_at(sub_along[i], height_at(sub_depth[i], v + (j + 0.5) / kSub - 0.5));
              if (c < 0) continue;
              ++(t.black[static_cast<std::size_t>(c)] ? n_ink : n_paper);
            }
          }
          if (n_ink + n_paper == 0) continue;  // the wall shows through
          for (int ch = 0; ch < Channels; ++ch) {
            const int wall_part = (kSamples - n_ink - n_paper) * dst[ch];
            dst[ch] = static_cast<std::uint8_t>((wall_part + n_ink * ink.v[static_cast<std::size_t>(ch)] + n_paper * paper.v[static_cast<std::size_t>(ch)] + kSamples / 2) / kSamples);
          }
        }
      }
    }

    // Other robots: upright cylinders, drawn from the farthest to the nearest.
    if (robots.empty()) continue;
    hits.clear();
    for (std::size_t i = 0; i < robots.size(); ++i) {
      const RobotShape& r = robots[i];
      const double ox = r.pose.x - pose.x, oy = r.pose.y - pose.y;
      const double c = ox * ox + oy * oy - r.radius * r.radius;
      if (c <= 0) continue;  // the camera is inside it: its own body
      const double b = ox * azimuth_x + oy * azimuth_y;
      const double disc = b * b - c;
      if (disc < 0 || b <= 0) continue;
      const double root = std::sqrt(disc);
      const double t1 = b - root;
      if (t1 >= dist) continue;  // behind the wall
      hits.push_back({t1, b + root, i});
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.t1 > b.t1; });
    for (const Hit& h : hits) {
      const RobotShape& r = robots[h.robot];
      const double z1 = h.t1 / sc.stretch[uu], z2 = h.t2 / sc.stretch[uu];
      const double px = pose.x + h.t1 * azimuth_x, py = pose.y + h.t1 * azimuth_y;
      const Rgb base = sc.style.body(r.id);
      const Colour body{static_cast<float>(base.r), static_cast<float>(base.g), static_cast<float>(base.b)};
      const auto side = Pixel<Channels>::of(seen(body, lambert((px - r.pose.x) / r.radius, (py - r.pose.y) / r.radius), z1));
      const double rise = mount - spec_.robot_height;  // > 0: the camera looks down on the lid
      const double side_top = cy + fy * rise / z1, side_bottom = cy + fy * mount / z1;
      double paint_top = side_top;
      if (rise > 0) paint_top = cy + fy * rise / z2;
      const int v0 = std::max(0, floor_within(paint_top + 0.5, 0, H));
      const int v1 = std::min(H - 1, floor_within(side_bottom + 0.5, 0, H));
      const auto lid = Pixel<Channels>::of(seen(mix(body, Colour{255, 255, 255}, 0.35f), 1.0f, z1));
      for (int v = v0; v <= v1; ++v) {
        std::uint8_t* dst = col + v * Channels;
        const double w_side = coverage(v, side_top, side_bottom);
        const double w_lid = rise > 0 ? coverage(v, paint_top, side_top) : 0.0;
        if (w_lid > 0) blend(dst, lid, std::min(1.0, w_lid));
        if (w_side >= 1.0) {
          side.store(dst);
        } else if (w_side > 0) {
          blend(dst, side, w_side);
        }
      }
    }
  }
}

}  // namespace vwg::sim
