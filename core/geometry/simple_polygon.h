#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::geometry {

// A simple polygon in the plane (keep-out zones, footprints): 3..kMaxVertices finite vertices, a
// positive area and no two edges that cross or touch except consecutive edges at their shared
// vertex. A closing vertex equal to the first (as GeoJSON writes rings) is dropped.
class SimplePolygon {
 public:
  static constexpr std::size_t kMinVertices = 3;
  static constexpr std::size_t kMaxVertices = 256;

  // Why `vertices` is not a simple polygon, in a sentence naming the first offending vertex or
  // edge; nullopt when it is one.
  static std::optional<std::string> error(std::span<const Point2D> vertices);

  // Throws std::invalid_argument with error()'s message.
  explicit SimplePolygon(std::vector<Point2D> vertices);

  const std::vector<Point2D>& vertices() const { return vertices_; }
  // Positive: the vertices run counter-clockwise.
  double signed_area_m2() const;
  // Even-odd rule; a point exactly on an edge may fall on either side.
  bool contains(Point2D point) const;
  Point2D min_corner() const { return min_; }
  Point2D max_corner() const { return max_; }

 private:
  std::vector<Point2D> vertices_;
  Point2D min_;
  Point2D max_;
};

}  // namespace mobot::geometry
