#include "core/geometry/simple_polygon.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mobot::geometry {
namespace {

// Twice the signed area of the triangle (a, b, c): > 0 when c lies left of a -> b.
double orientation(Point2D a, Point2D b, Point2D c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

int sign(double value) { return (value > 0.0) - (value < 0.0); }

// `c` collinear with a -> b: does it lie within the segment's box?
bool within_box(Point2D a, Point2D b, Point2D c) {
  return std::min(a.x, b.x) <= c.x && c.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= c.y &&
         c.y <= std::max(a.y, b.y);
}

// Closed segments [a, b] and [c, d] share a point (crossing, touching or overlapping).
bool segments_meet(Point2D a, Point2D b, Point2D c, Point2D d) {
  const int o1 = sign(orientation(a, b, c));
  const int o2 = sign(orientation(a, b, d));
  const int o3 = sign(orientation(c, d, a));
  const int o4 = sign(orientation(c, d, b));
  if (o1 != o2 && o3 != o4) return true;
  return (o1 == 0 && within_box(a, b, c)) || (o2 == 0 && within_box(a, b, d)) ||
         (o3 == 0 && within_box(c, d, a)) || (o4 == 0 && within_box(c, d, b));
}

std::span<const Point2D> without_closing_vertex(std::span<const Point2D> vertices) {
  if (vertices.size() > 1 && vertices.front() == vertices.back()) {
    return vertices.first(vertices.size() - 1);
  }
  return vertices;
}

double twice_signed_area(std::span<const Point2D> v) {
  double sum = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Point2D& a = v[i];
    const Point2D& b = v[(i + 1) % v.size()];
    sum += a.x * b.y - b.x * a.y;
  }
  return sum;
}

std::string edge_name(std::size_t i, std::size_t n) {
  return std::to_string(i) + "-" + std::to_string((i + 1) % n);
}

}  // namespace

std::optional<std::string> SimplePolygon::error(std::span<const Point2D> input) {
  const std::span<const Point2D> v = without_closing_vertex(input);
  const std::size_t n = v.size();
  if (n < kMinVertices || n > kMaxVertices) {
    return "a polygon needs " + std::to_string(kMinVertices) + " to " +
           std::to_string(kMaxVertices) + " vertices, got " + std::to_string(n);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(v[i].x) || !std::isfinite(v[i].y)) {
      return "vertex " + std::to_string(i) + " is not finite";
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (v[i] == v[(i + 1) % n]) {
      return "vertex " + std::to_string((i + 1) % n) + " repeats vertex " + std::to_string(i);
    }
  }
  // All vertices on one line: judged relative to the polygon's extent, so a zone in millimetres
  // and one in kilometres are treated alike; what is left is rounding noise.
  std::size_t farthest = 0;
  double extent2 = 0.0;
  for (std::size_t i = 1; i < n; ++i) {
    const double d2 = (v[i].x - v[0].x) * (v[i].x - v[0].x) + (v[i].y - v[0].y) * (v[i].y - v[0].y);
    if (d2 > extent2) {
      extent2 = d2;
      farthest = i;
    }
  }
  bool collinear = true;
  for (std::size_t i = 1; i < n && collinear; ++i) {
    collinear = std::abs(orientation(v[0], v[farthest], v[i])) <= 1e-12 * extent2;
  }
  if (collinear) return "the polygon has no area (its vertices are collinear)";
  for (std::size_t i = 0; i < n; ++i) {
    const Point2D a = v[i];
    const Point2D b = v[(i + 1) % n];
    // Consecutive edges share a vertex; they are only wrong when the second doubles back along
    // the first (a spike of zero width).
    const Point2D c = v[(i + 2) % n];
    if (sign(orientation(a, b, c)) == 0 &&
        (c.x - b.x) * (a.x - b.x) + (c.y - b.y) * (a.y - b.y) > 0.0) {
      return "edge " + edge_name((i + 1) % n, n) + " doubles back along edge " + edge_name(i, n) +
             " (the polygon intersects itself)";
    }
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // the closing edge is consecutive to the first
      if (segments_meet(a, b, v[j], v[(j + 1) % n])) {
        return "edge " + edge_name(i, n) + " meets edge " + edge_name(j, n) +
               " (the polygon intersects itself)";
      }
    }
  }
  if (twice_signed_area(v) == 0.0) return "the polygon has no area";
  return std::nullopt;
}

SimplePolygon::SimplePolygon(std::vector<Point2D> vertices) {
  if (const auto why = error(vertices)) throw std::invalid_argument(*why);
  if (vertices.front() == vertices.back()) vertices.pop_back();
  vertices_ = std::move(vertices);
  min_ = max_ = vertices_.front();
  for (const Point2D& p : vertices_) {
    min_ = {std::min(min_.x, p.x), std::min(min_.y, p.y)};
    max_ = {std::max(max_.x, p.x), std::max(max_.y, p.y)};
  }
}

double SimplePolygon::signed_area_m2() const { return 0.5 * twice_signed_area(vertices_); }

bool SimplePolygon::contains(Point2D point) const {
  if (point.x < min_.x || point.x > max_.x || point.y < min_.y || point.y > max_.y) return false;
  bool inside = false;
  const std::size_t n = vertices_.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Point2D& a = vertices_[i];
    const Point2D& b = vertices_[j];
    if ((a.y > point.y) != (b.y > point.y) &&
        point.x < (b.x - a.x) * (point.y - a.y) / (b.y - a.y) + a.x) {
      inside = !inside;
    }
  }
  return inside;
}

}  // namespace mobot::geometry
