#include "vwg/sim/overview3d.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "vwg/error.hpp"
#include "vwg/perception/apriltag.hpp"
#include "vwg/sim/physics.hpp"
#include "vwg/sim/raycast.hpp"
#include "vwg/sim/render2d.hpp"
#include "vwg/sim/view3d.hpp"

namespace vwg::sim {

namespace {

/// floor(v) as an int within [lo - 1, hi + 1], clamped before the conversion (which is undefined
/// out of int's range: a point near the eye projects far out).
int floor_within(double v, int lo, int hi) { return static_cast<int>(std::floor(std::clamp(v, lo - 1.0, hi + 1.0))); }

cv::Vec3b to_pixel(Colour c) { return {to_byte(c.r), to_byte(c.g), to_byte(c.b)}; }

// --- the look -----------------------------------------------------------------------------------

const Colour kBackgroundTop{44, 49, 58};
const Colour kBackgroundBottom{78, 86, 98};
const Colour kFloorFree{238, 235, 228};
const Colour kFloorUnknown{168, 172, 180};
const Colour kFloorLine{208, 204, 196};  // 1 m tiles, faint
const Colour kWallSide{228, 222, 210};
const Colour kWallTop{86, 94, 110};
const Colour kMarkerFrame{230, 150, 0};  // the 2D view's marker colour
const Colour kPaper{250, 250, 246};
const Colour kInk{18, 18, 20};
constexpr float kShadow = 0.74f;             // floor brightness in a wall's shadow
constexpr double kLightAfterView = 1.15;     // the light comes from this far (radians) to the viewer's right
constexpr double kLightElevation = 0.85;     // radians above the horizon
constexpr double kTileLine = 0.02;           // width of the floor's 1 m lines, metres

/// Ambient plus Lambert: faces turned away from the light keep 45 % of their colour.
float shade(const Vec3& normal, const Vec3& light) { return lambert(normal.dot(light), 0.45, 0.55); }

// --- the scene as polygons ------------------------------------------------------------------------

enum class Material : std::uint8_t { Flat, Side, Floor, Tag };

/// A convex planar polygon.
struct Polygon {
  std::vector<Vec3> points;
  Vec3 normal = Vec3::Zero();
  Material material = Material::Flat;
  Colour colour;
  int tag = -1;  // index into Scene::tags for Material::Tag
};

/// A tag texture on a wall: the square's top-left corner, its axes (right along the wall, down)
/// and its bitmap.
struct TagTexture {
  Vec3 corner = Vec3::Zero(), along = Vec3::Zero(), down = Vec3::Zero();
  double side = 0;
  int cells = 0;
  std::vector<std::uint8_t> black;
};

struct Scene {
  std::vector<Polygon> polygons;
  std::vector<TagTexture> tags;
};

Vec3 grid_point(const OccupancyGrid& g, double u, double v, double z) {
  double x, y;
  g.grid_to_world(u, v, x, y);
  return Vec3(x, y, z);
}

/// A unit world-frame normal of a grid-axis direction (du, dv).
Vec3 grid_normal(const OccupancyGrid& g, double du, double dv) {
  const double c = std::cos(g.origin.theta), s = std::sin(g.origin.theta);
  return Vec3(c * du - s * dv, s * du + c * dv, 0.0);
}

bool facing_eye(const OverviewCamera& cam, const Vec3& point, const Vec3& normal) {
  if (cam.orthographic) return normal.dot(cam.forward) < 0;
  return normal.dot(cam.eye - point) > 0;
}

void add_walls(Scene& scene, const OccupancyGrid& g, double wall_height, int threshold, const OverviewCamera& cam, const Vec3& light) {
  // Tops: the merged rectangles, all one flat colour, so their seams do not show.
  for (const auto& r : PhysicsWorld::merge_walls(g, threshold)) {
    Polygon p;
    p.points = {grid_point(g, r.col0, r.row0, wall_height), grid_point(g, r.col1, r.row0, wall_height),
                grid_point(g, r.col1, r.row1, wall_height), grid_point(g, r.col0, r.row1, wall_height)};
    p.normal = Vec3::UnitZ();
    p.colour = kWallTop;
    scene.polygons.push_back(std::move(p));
  }
  // Sides: only the faces between a wall cell and a free one (boxes of touching rectangles would
  // put faces inside the walls, whose edges flicker through the tops), merged into runs.
  auto blocked = [&](int row, int col) { return g.blocked(row, col, threshold); };
  auto add_side = [&](const Vec3& a, const Vec3& b, const Vec3& normal) {
    if (!facing_eye(cam, (a + b) * 0.5, normal)) return;
    Polygon p;
    const Vec3 up(0, 0, wall_height);
    p.points = {a, b, b + up, a + up};
    p.normal = normal;
    p.material = Material::Side;
    p.colour = kWallSide * shade(normal, light);
    scene.polygons.push_back(std::move(p));
  };
  for (int row = 0; row < g.height; ++row) {
    for (int side = 0; side < 2; ++side) {  // 0: the face below the cell (-v), 1: above (+v)
      const int dv = side == 0 ? -1 : 1;
      const double v = side == 0 ? row : row + 1;
      for (int col = 0; col < g.width;) {
        if (!blocked(row, col) || blocked(row + dv, col)) {
          ++col;
          continue;
        }
        const int start = col;
        while (col < g.width && blocked(row, col) && !blocked(row + dv, col)) ++col;
        add_side(grid_point(g, start, v, 0), grid_point(g, col, v, 0), grid_normal(g, 0, dv));
      }
    }
  }
  for (int col = 0; col < g.width; ++col) {
    for (int side = 0; side < 2; ++side) {  // 0: the face left of the cell (-u), 1: right (+u)
      const int du = side == 0 ? -1 : 1;
      const double u = side == 0 ? col : col + 1;
      for (int row = 0; row < g.height;) {
        if (!blocked(row, col) || blocked(row, col + du)) {
          ++row;
          continue;
        }
        const int start = row;
        while (row < g.height && blocked(row, col) && !blocked(row, col + du)) ++row;
        add_side(grid_point(g, u, start, 0), grid_point(g, u, row, 0), grid_normal(g, du, 0));
      }
    }
  }
}

void add_markers(Scene& scene, const OccupancyGrid& g, std::span<const WallMarker> markers, const OverviewCamera& cam) {
  const perception::TagFamilyInfo family = perception::family_info("tag36h11");
  for (const WallMarker& m : markers) {
    const Vec3 n(std::cos(m.facing), std::sin(m.facing), 0);
    const Vec3 along(-n.y(), n.x(), 0);  // to the right of someone facing the marker
    // Off the wall a little so the z-buffer keeps it in front; a slanted wall is a staircase of
    // cells that can stand up to a cell proud of the marker's plane, so move those out further.
    const double slant = std::remainder(m.facing - g.origin.theta, std::numbers::pi / 2);
    const double lift = std::fabs(slant) > 1e-6 ? g.resolution : 0.0;
    const Vec3 centre(m.x, m.y, m.height);
    if (!facing_eye(cam, centre, n)) continue;
    const double half = m.size * family.total_width / family.width_at_border / 2;
    auto square = [&](double h, double offset) {
      const Vec3 c = centre + n * (offset + lift), up(0, 0, h);
      return std::vector<Vec3>{c - along * h + up, c + along * h + up, c + along * h - up, c - along * h - up};
    };
    Polygon frame;
    frame.points = square(half + 0.05, 0.006);
    frame.normal = n;
    frame.colour = kMarkerFrame;
    scene.polygons.push_back(std::move(frame));

    TagTexture tex;
    const perception::GrayImage bitmap = perception::render_tag("tag36h11", m.id, 0, 1);
    tex.cells = bitmap.width;
    tex.black.resize(bitmap.pixels.size());
    for (std::size_t i = 0; i < bitmap.pixels.size(); ++i) tex.black[i] = bitmap.pixels[i] < 128 ? 1 : 0;
    Polygon tag;
    tag.points = square(half, 0.012);
    tex.corner = tag.points[0];
    tex.along = along;
    tex.down = -Vec3::UnitZ();
    tex.side = 2 * half;
    tag.normal = n;
    tag.material = Material::Tag;
    tag.tag = static_cast<int>(scene.tags.size());
    scene.tags.push_back(std::move(tex));
    scene.polygons.push_back(std::move(tag));
  }
}

void add_robots(Scene& scene, std::span<const RobotShape> robots, double height, const OverviewCamera& cam, const Vec3& light) {
  const RenderStyle style;
  constexpr int kFacets = 48;
  for (const RobotShape& r : robots) {
    const Rgb c = style.body(r.id);
    const Colour body{static_cast<float>(c.r), static_cast<float>(c.g), static_cast<float>(c.b)};
    const Vec3 base(r.pose.x, r.pose.y, 0), up(0, 0, height);
    Polygon lid;
    for (int i = 0; i < kFacets; ++i) {
      const double a0 = 2 * std::numbers::pi * i / kFacets, a1 = 2 * std::numbers::pi * (i + 1) / kFacets;
      const Vec3 p0 = base + Vec3(r.radius * std::cos(a0), r.radius * std::sin(a0), 0);
      const Vec3 p1 = base + Vec3(r.radius * std::cos(a1), r.radius * std::sin(a1), 0);
      const Vec3 normal(std::cos(0.5 * (a0 + a1)), std::sin(0.5 * (a0 + a1)), 0);
      lid.points.push_back(p0 + up);
      if (!facing_eye(cam, (p0 + p1) * 0.5, normal)) continue;
      Polygon side;
      side.points = {p0, p1, p1 + up, p0 + up};
      side.normal = normal;
      side.colour = body * shade(normal, light);
      scene.polygons.push_back(std::move(side));
    }
    lid.normal = Vec3::UnitZ();
    lid.colour = mix(body, Colour{255, 255, 255}, 0.25f) * shade(lid.normal, light);
    scene.polygons.push_back(std::move(lid));
    // The heading: a white arrowhead on the lid.
    const double h = r.pose.theta;
    auto at = [&](double angle, double k) -> Vec3 {
      return base + Vec3(k * r.radius * std::cos(h + angle), k * r.radius * std::sin(h + angle), height + 0.004);
    };
    Polygon arrow;
    arrow.points = {at(0, 0.85), at(2.5, 0.55), at(std::numbers::pi, 0.15), at(-2.5, 0.55)};
    arrow.normal = Vec3::UnitZ();
    arrow.colour = Colour{250, 250, 250};
    // The arrow is a dart (not convex): draw it as two triangles.
    Polygon left = arrow, right = arrow;
    left.points = {arrow.points[0], arrow.points[1], arrow.points[2]};
    right.points = {arrow.points[0], arrow.points[2], arrow.points[3]};
    scene.polygons.push_back(std::move(left));
    scene.polygons.push_back(std::move(right));
  }
}

// --- rasterizer -----------------------------------------------------------------------------------

/// A projected vertex: pixel position and a depth key that is linear in screen space and larger
/// when nearer (1/depth in perspective, -depth orthographic).
struct Projected {
  double x, y, key;
};

class Raster {
 public:
  Raster(int width, int height) : width_(width), height_(height) {
    depth_.assign(static_cast<std::size_t>(width) * height, -std::numeric_limits<float>::infinity());
    owner_.assign(static_cast<std::size_t>(width) * height, -1);
  }

  void triangle(const Projected& a, const Projected& b, const Projected& c, int polygon) {
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::fabs(area) < 1e-12) return;
    const double x0 = std::min({a.x, b.x, c.x}), x1 = std::max({a.x, b.x, c.x});
    const double y0 = std::min({a.y, b.y, c.y}), y1 = std::max({a.y, b.y, c.y});
    // Pixel centres inside the bounding box: ceil(x0) = -floor(-x0).
    const int u0 = std::max(0, -floor_within(-x0, -width_, 0)), u1 = std::min(width_ - 1, floor_within(x1, 0, width_));
    const int v0 = std::max(0, -floor_within(-y0, -height_, 0)), v1 = std::min(height_ - 1, floor_within(y1, 0, height_));
    const double inv = 1.0 / area;
    for (int v = v0; v <= v1; ++v) {
      for (int u = u0; u <= u1; ++u) {
        // Barycentric weights of the pixel centre (u, v); inside when all are >= 0 (shared edges
        // are drawn twice, which the depth test makes harmless).
        const double wa = ((b.x - u) * (c.y - v) - (b.y - v) * (c.x - u)) * inv;
        const double wb = ((c.x - u) * (a.y - v) - (c.y - v) * (a.x - u)) * inv;
        const double wc = 1.0 - wa - wb;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const auto key = static_cast<float>(wa * a.key + wb * b.key + wc * c.key);
        const std::size_t i = static_cast<std::size_t>(v) * width_ + u;
        if (key > depth_[i]) {
          depth_[i] = key;
          owner_[i] = polygon;
        }
      }
    }
  }

  int owner(int u, int v) const { return owner_[static_cast<std::size_t>(v) * width_ + u]; }

 private:
  int width_, height_;
  std::vector<float> depth_;
  std::vector<int> owner_;
};

/// The part of a convex polygon at least `near` metres in front of a perspective eye
/// (Sutherland-Hodgman against that one plane): the floor and the wall tops of a map larger than
/// the framed part can reach behind the eye.
std::vector<Vec3> clip_near(const std::vector<Vec3>& points, const OverviewCamera& cam, double near) {
  auto depth = [&](const Vec3& p) { return (p - cam.eye).dot(cam.forward) - near; };
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 a = points[i], b = points[(i + 1) % points.size()];
    const double da = depth(a), db = depth(b);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

/// A camera for the supersampled image: the same view, `factor` times the pixels.
OverviewCamera scaled(const OverviewCamera& cam, int factor) {
  OverviewCamera s = cam;
  s.width = cam.width * factor;
  s.height = cam.height * factor;
  s.focal = cam.focal * factor;
  // Pixel (u, v) of the image covers [u - 0.5, u + 0.5]: the big pixels' edges must stay edges.
  s.cu = (cam.cu + 0.5) * factor - 0.5;
  s.cv = (cam.cv + 0.5) * factor - 0.5;
  return s;
}

/// Which floor cells lie in a wall's shadow: a cell is shadowed if a wall stands between it and
/// the light within the distance at which a wall's top still hides the light.
std::vector<float> floor_shadows(const OccupancyGrid& g, double wall_height, int threshold, const Vec3& light) {
  std::vector<float> lit(g.data.size(), 1.0f);
  const double horizontal = std::hypot(light.x(), light.y());
  if (horizontal < 1e-9) return lit;
  const double reach = wall_height * horizontal / light.z();
  const double angle = std::atan2(light.y(), light.x());
  const GridRaycaster caster(g, threshold);
  for (int row = 0; row < g.height; ++row) {
    for (int col = 0; col < g.width; ++col) {
      if (g.blocked(row, col, threshold)) continue;
      double x, y;
      g.grid_to_world(col + 0.5, row + 0.5, x, y);
      if (caster.range(x, y, angle, reach) < reach) lit[static_cast<std::size_t>(row) * g.width + col] = 0.0f;
    }
  }
  return lit;
}

/// The part of the world to frame: the free cells' bounding box and a metre around it (so the
/// walls that bound them are in), within the map; the whole map when nothing is free. A map whose
/// unexplored outside is stored as walls (willow) is thus framed on its building.
void framed_box(const OccupancyGrid& g, int threshold, int& col0, int& row0, int& col1, int& row1) {
  col0 = g.width;
  row0 = g.height;
  col1 = -1;
  row1 = -1;
  for (int r = 0; r < g.height; ++r) {
    for (int c = 0; c < g.width; ++c) {
      const int value = g.at(r, c);
      if (value < 0 || value >= threshold) continue;
      col0 = std::min(col0, c);
      col1 = std::max(col1, c);
      row0 = std::min(row0, r);
      row1 = std::max(row1, r);
    }
  }
  if (col1 < 0) {
    col0 = row0 = 0;
    col1 = g.width - 1;
    row1 = g.height - 1;
    return;
  }
  const int pad = static_cast<int>(std::ceil(1.0 / g.resolution));
  col0 = std::max(0, col0 - pad);
  row0 = std::max(0, row0 - pad);
  col1 = std::min(g.width - 1, col1 + pad);
  row1 = std::min(g.height - 1, row1 + pad);
}

void check_grid(const OccupancyGrid& g) {
  if (g.width <= 0 || g.height <= 0 || g.data.size() != static_cast<std::size_t>(g.width) * g.height) {
    throw SchemaError("grid", "expected width × height cells");
  }
  if (!std::isfinite(g.resolution) || g.resolution <= 0) throw SchemaError("grid.resolution", "expected a finite value > 0");
  if (!std::isfinite(g.origin.x) || !std::isfinite(g.origin.y) || !std::isfinite(g.origin.theta)) {
    throw SchemaError("grid.origin", "expected finite x, y, yaw");
  }
}

}  // namespace

// --- camera -------------------------------------------------------------------------------------

void check_overview_view(const OverviewView& v) {
  if (v.width < 16 || v.width > 8192) throw SchemaError("view.width", "expected 16 to 8192 pixels");
  if (v.height < 16 || v.height > 8192) throw SchemaError("view.height", "expected 16 to 8192 pixels");
  if (!std::isfinite(v.azimuth)) throw SchemaError("view.azimuth", "expected a finite angle, radians");
  if (!std::isfinite(v.elevation) || v.elevation <= 0 || v.elevation > std::numbers::pi / 2 + 1e-12) {
    throw SchemaError("view.elevation", "expected an angle in (0, π/2] radians");
  }
  if (!std::isfinite(v.fov) || v.fov < 0 || v.fov >= std::numbers::pi) throw SchemaError("view.fov", "expected 0 (orthographic) or a field of view in (0, π) radians");
  if (!std::isfinite(v.robot_height) || v.robot_height <= 0) throw SchemaError("view.robot_height", "expected a finite height > 0, metres");
  if (v.supersample < 1 || v.supersample > 4) throw SchemaError("view.supersample", "expected 1 to 4");
  if (!v.fit) {
    if (!std::isfinite(v.target_x) || !std::isfinite(v.target_y) || !std::isfinite(v.target_z)) {
      throw SchemaError("view.target", "expected a finite point, metres");
    }
    if (v.fov == 0 && !(std::isfinite(v.scale) && v.scale > 0)) throw SchemaError("view.scale", "expected pixels per metre > 0 (orthographic, fit off)");
    if (v.fov > 0 && !(std::isfinite(v.distance) && v.distance > 0)) throw SchemaError("view.distance", "expected an eye distance > 0, metres (perspective, fit off)");
  }
}

OverviewCamera overview_camera(const OccupancyGrid& g, double wall_height, const OverviewView& view, int threshold) {
  check_grid(g);
  check_overview_view(view);
  if (!std::isfinite(wall_height) || wall_height <= 0) throw SchemaError("wall_height", "expected a finite height > 0, metres");
  OverviewCamera cam;
  cam.width = view.width;
  cam.height = view.height;
  cam.orthographic = view.fov == 0;
  const double ca = std::cos(view.azimuth), sa = std::sin(view.azimuth);
  const double ce = std::cos(view.elevation), se = std::sin(view.elevation);
  const Vec3 forward(-ce * ca, -ce * sa, -se);
  const Vec3 right(-sa, ca, 0);
  const Vec3 down = forward.cross(right);
  cam.forward = forward;
  cam.right = right;
  cam.down = down;
  cam.cu = PinholeCamera::centre_of(view.width);
  cam.cv = PinholeCamera::centre_of(view.height);

  // What must fit: the free part of the map and its walls, from the floor to the wall tops.
  int col0, row0, col1, row1;
  framed_box(g, threshold, col0, row0, col1, row1);
  std::vector<Vec3> corners;
  for (double z : {0.0, wall_height}) {
    for (auto [u, v] : {std::pair{col0, row0}, {col1 + 1, row0}, {col1 + 1, row1 + 1}, {col0, row1 + 1}}) {
      corners.push_back(grid_point(g, u, v, z));
    }
  }
  Vec3 target(view.target_x, view.target_y, view.target_z);
  double radius = 0;
  if (view.fit) {
    target = (grid_point(g, col0, row0, 0) + grid_point(g, col1 + 1, row1 + 1, 0)) * 0.5;
  }
  for (const Vec3& c : corners) radius = std::max(radius, (c - target).norm());
  radius = std::max(radius, 1.0);

  const double margin_u = 0.04 * view.width, margin_v = 0.05 * view.height;
  const double room_u = view.width - 2 * margin_u, room_v = view.height - 2 * margin_v;
  if (cam.orthographic) {
    cam.eye = target - forward * (4 * radius + 10);
    cam.focal = view.scale;
    if (view.fit) {
      double lo_u = 1e300, hi_u = -1e300, lo_v = 1e300, hi_v = -1e300;
      for (const Vec3& c : corners) {
        const Vec3 d = c - target;
        lo_u = std::min(lo_u, d.dot(right));
        hi_u = std::max(hi_u, d.dot(right));
        lo_v = std::min(lo_v, d.dot(down));
        hi_v = std::max(hi_v, d.dot(down));
      }
      cam.focal = std::min(room_u / std::max(hi_u - lo_u, 1e-9), room_v / std::max(hi_v - lo_v, 1e-9));
      cam.cu -= cam.focal * 0.5 * (lo_u + hi_u);
      cam.cv -= cam.focal * 0.5 * (lo_v + hi_v);
    }
    return cam;
  }

  cam.focal = PinholeCamera::focal_for(view.width, view.fov);
  if (!view.fit) {
    cam.eye = target - forward * view.distance;
    return cam;
  }
  // The nearest eye distance at which the corners fit the image (the frame shrinks as the eye
  // backs away), then the principal point shifted to centre them.
  struct Extent {
    double lo_u, hi_u, lo_v, hi_v;
  };
  auto extent = [&](double distance) {
    const Vec3 eye = target - forward * distance;
    Extent e{1e300, -1e300, 1e300, -1e300};
    for (const Vec3& c : corners) {
      const Vec3 p = c - eye;
      const double z = p.dot(forward);
      const double u = p.dot(right) / z, v = p.dot(down) / z;
      e.lo_u = std::min(e.lo_u, u);
      e.hi_u = std::max(e.hi_u, u);
      e.lo_v = std::min(e.lo_v, v);
      e.hi_v = std::max(e.hi_v, v);
    }
    return e;
  };
  auto fits = [&](double distance) {
    const Extent e = extent(distance);
    return cam.focal * (e.hi_u - e.lo_u) <= room_u && cam.focal * (e.hi_v - e.lo_v) <= room_v;
  };
  double near = 1.05 * radius, far = near;
  if (!fits(near)) {
    while (!fits(far)) {
      near = far;
      far *= 2;
    }
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (near + far);
      (fits(mid) ? far : near) = mid;
    }
  }
  const Extent e = extent(far);
  cam.eye = target - forward * far;
  cam.cu -= cam.focal * 0.5 * (e.lo_u + e.hi_u);
  cam.cv -= cam.focal * 0.5 * (e.lo_v + e.hi_v);
  return cam;
}

// --- rendering ----------------------------------------------------------------------------------

cv::Mat render_overview(const OccupancyGrid& g, double wall_height, std::span<const WallMarker> markers,
                        std::span<const RobotShape> robots, const OverviewView& view, int threshold) {
  const OverviewCamera cam = overview_camera(g, wall_height, view, threshold);
  check_markers(markers, wall_height);
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const RobotShape& r = robots[i];
    if (!std::isfinite(r.pose.x) || !std::isfinite(r.pose.y) || !std::isfinite(r.pose.theta)) {
      throw SchemaError("robots[" + std::to_string(i) + "].pose", "expected finite x, y, yaw");
    }
    if (!std::isfinite(r.radius) || r.radius <= 0) throw SchemaError("robots[" + std::to_string(i) + "].radius", "expected a finite radius > 0");
  }
  // The light comes from the viewer's right and above, so the sides facing the viewer differ in
  // brightness and the shadows fall to the left, where they can be seen.
  const double light_azimuth = view.azimuth + kLightAfterView;
  const Vec3 light(std::cos(kLightElevation) * std::cos(light_azimuth), std::cos(kLightElevation) * std::sin(light_azimuth),
                   std::sin(kLightElevation));

  Scene scene;
  {
    Polygon floor;
    floor.points = {grid_point(g, 0, 0, 0), grid_point(g, g.width, 0, 0), grid_point(g, g.width, g.height, 0), grid_point(g, 0, g.height, 0)};
    floor.normal = Vec3::UnitZ();
    floor.material = Material::Floor;
    scene.polygons.push_back(std::move(floor));
  }
  add_walls(scene, g, wall_height, threshold, cam, light);
  add_markers(scene, g, markers, cam);
  add_robots(scene, robots, view.robot_height, cam, light);

  const int factor = view.supersample;
  const OverviewCamera big = scaled(cam, factor);
  Raster raster(big.width, big.height);
  const double near_plane = 0.05;  // metres in front of the eye
  std::vector<Projected> corners;
  for (std::size_t k = 0; k < scene.polygons.size(); ++k) {
    const Polygon& p = scene.polygons[k];
    corners.clear();
    for (const Vec3& q : big.orthographic ? p.points : clip_near(p.points, big, near_plane)) {
      double u, v, depth;
      big.project(q, u, v, depth);
      corners.push_back({u, v, big.orthographic ? -depth : 1.0 / depth});
    }
    if (corners.size() < 3) continue;
    for (std::size_t i = 1; i + 1 < corners.size(); ++i) raster.triangle(corners[0], corners[i], corners[i + 1], static_cast<int>(k));
  }

  // Shade each sample by what it shows.
  const std::vector<float> lit = floor_shadows(g, wall_height, threshold, light);
  auto lit_at = [&](double u, double v) {  // bilinear between cell centres: soft shadow edges
    const double a = u - 0.5, b = v - 0.5;
    const int c0 = floor_within(a, 0, g.width), r0 = floor_within(b, 0, g.height);
    const double fa = a - c0, fb = b - r0;
    double sum = 0;
    for (int dr = 0; dr < 2; ++dr) {
      for (int dc = 0; dc < 2; ++dc) {
        const int r = std::clamp(r0 + dr, 0, g.height - 1), c = std::clamp(c0 + dc, 0, g.width - 1);
        sum += lit[static_cast<std::size_t>(r) * g.width + c] * (dc ? fa : 1 - fa) * (dr ? fb : 1 - fb);
      }
    }
    return sum;
  };
  cv::Mat big_image(big.height, big.width, CV_8UC3);
  for (int v = 0; v < big.height; ++v) {
    auto* row = big_image.ptr<cv::Vec3b>(v);
    const Colour sky = mix(kBackgroundTop, kBackgroundBottom, static_cast<float>(v) / std::max(1, big.height - 1));
    for (int u = 0; u < big.width; ++u) {
      const int owner = raster.owner(u, v);
      if (owner < 0) {
        row[u] = to_pixel(sky);
        continue;
      }
      const Polygon& p = scene.polygons[static_cast<std::size_t>(owner)];
      if (p.material == Material::Flat) {
        row[u] = to_pixel(p.colour);
        continue;
      }
      // Where the pixel's ray meets the polygon's plane.
      Vec3 origin, dir;
      big.ray(u, v, origin, dir);
      const double denom = dir.dot(p.normal);
      const double t = std::fabs(denom) > 1e-12 ? (p.points[0] - origin).dot(p.normal) / denom : 0.0;
      const Vec3 hit = origin + dir * t;
      if (p.material == Material::Side) {
        // Darker towards the floor (the light the floor and the other walls do not send back
        // there): the walls' feet read as corners rather than as flat cut-outs.
        const float height = static_cast<float>(std::clamp(hit.z() / wall_height, 0.0, 1.0));
        row[u] = to_pixel(p.colour * (0.8f + 0.2f * height));
      } else if (p.material == Material::Floor) {
        double gu, gv;
        g.world_to_grid(hit.x(), hit.y(), gu, gv);
        const int col = std::clamp(floor_within(gu, 0, g.width), 0, g.width - 1);
        const int r = std::clamp(floor_within(gv, 0, g.height), 0, g.height - 1);
        const int value = g.at(r, col);
        Colour c = value < 0 ? kFloorUnknown : mix(kFloorFree, kFloorUnknown, static_cast<float>(std::min(value, 100)) / 100.0f);
        const double fx = hit.x() - std::floor(hit.x()), fy = hit.y() - std::floor(hit.y());
        if (value >= 0 && (fx < kTileLine || fy < kTileLine)) c = kFloorLine;
        c = c * static_cast<float>(kShadow + (1 - kShadow) * lit_at(gu, gv));
        row[u] = to_pixel(c);
      } else {
        const TagTexture& tex = scene.tags[static_cast<std::size_t>(p.tag)];
        const Vec3 d = hit - tex.corner;
        const int cu = std::clamp(static_cast<int>(d.dot(tex.along) / tex.side * tex.cells), 0, tex.cells - 1);
        const int cv = std::clamp(static_cast<int>(d.dot(tex.down) / tex.side * tex.cells), 0, tex.cells - 1);
        row[u] = to_pixel(tex.black[static_cast<std::size_t>(cv) * tex.cells + cu] ? kInk : kPaper);
      }
    }
  }
  cv::Mat image;
  cv::resize(big_image, image, cv::Size(cam.width, cam.height), 0, 0, cv::INTER_AREA);

  if (view.labels) {
    const double font = std::clamp(view.width / 2200.0, 0.35, 0.8);
    // Text centred above (u, v) on a translucent dark box, drawn over everything so that a label
    // stays readable where a wall hides what it names.
    std::vector<cv::Rect> taken;
    auto label = [&](const std::string& text, double u, double v, const cv::Scalar& colour) {
      int base = 0;
      const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, font, 1, &base);
      cv::Point origin(static_cast<int>(std::lround(u - size.width / 2.0)), static_cast<int>(std::lround(v - 6)));
      cv::Rect box(origin.x - 3, origin.y - size.height - 3, size.width + 6, size.height + base + 5);
      // Labels of things close together would cover each other: move up past those already placed.
      for (int tries = 0; tries < 8; ++tries) {
        const bool clear = std::none_of(taken.begin(), taken.end(), [&](const cv::Rect& t) { return (t & box).area() > 0; });
        if (clear) break;
        origin.y -= box.height + 1;
        box.y -= box.height + 1;
      }
      taken.push_back(box);
      const cv::Rect clipped = box & cv::Rect(0, 0, image.cols, image.rows);
      if (clipped.area() > 0) {
        cv::Mat region = image(clipped);
        const cv::Mat dark(region.size(), region.type(), cv::Scalar(24, 26, 32));
        cv::addWeighted(region, 0.35, dark, 0.65, 0.0, region);
      }
      cv::putText(image, text, origin, cv::FONT_HERSHEY_SIMPLEX, font, colour, 1, cv::LINE_AA);
    };
    for (const WallMarker& m : markers) {
      double u, v;
      // Above the wall top, a little in front of the marker, so the text sits over its room side.
      if (!cam.project(m.x + 0.3 * std::cos(m.facing), m.y + 0.3 * std::sin(m.facing), wall_height + 0.2, u, v)) continue;
      if (std::fabs(u) > 1e6 || std::fabs(v) > 1e6) continue;
      label(m.label.empty() ? "#" + std::to_string(m.id) : m.label + " #" + std::to_string(m.id), u, v, cv::Scalar(255, 214, 140));
    }
    const RenderStyle style;
    for (const RobotShape& r : robots) {
      double u, v;
      if (!cam.project(r.pose.x, r.pose.y, view.robot_height + 0.25, u, v)) continue;
      if (std::fabs(u) > 1e6 || std::fabs(v) > 1e6) continue;
      const Rgb c = style.body(r.id);
      // The bodies' colours, lightened: readable on the dark box. People come as ids below zero.
      const std::string name = r.id < 0 ? "person " + std::to_string(-static_cast<long long>(r.id)) : "robot " + std::to_string(r.id);
      label(name, u, v, cv::Scalar((c.r + 255) / 2, (c.g + 255) / 2, (c.b + 255) / 2));
    }
  }
  return image;
}

}  // namespace vwg::sim
