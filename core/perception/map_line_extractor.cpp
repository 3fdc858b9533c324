#include "core/perception/map_line_extractor.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <span>

#include "core/perception/line_fitter.h"

namespace mobot::perception {
namespace {

// An inclusive index range [first, last] along a closed outline; last may exceed the outline's
// size, in which case indices wrap.
struct Piece {
  int first = 0;
  int last = 0;
};

cv::Mat wall_mask(const mapping::OccupancyGrid& grid, std::uint8_t occupied_min_value) {
  // One cell of padding: border following must not run along the image edge.
  cv::Mat mask = cv::Mat::zeros(grid.height() + 2, grid.width() + 2, CV_8U);
  const std::vector<std::uint8_t>& cells = grid.cells();
  for (int y = 0; y < grid.height(); ++y) {
    auto* row = mask.ptr<std::uint8_t>(y + 1);
    for (int x = 0; x < grid.width(); ++x) {
      const std::uint8_t v =
          cells[static_cast<std::size_t>(y) * static_cast<std::size_t>(grid.width()) +
                static_cast<std::size_t>(x)];
      if (v != mapping::OccupancyGrid::kUnknown && v >= occupied_min_value) row[x + 1] = 255;
    }
  }
  return mask;
}

const cv::Point& at(const std::vector<cv::Point>& outline, int index) {
  return outline[static_cast<std::size_t>(index % static_cast<int>(outline.size()))];
}

double chord_distance(const cv::Point& a, const cv::Point& b, const cv::Point& p) {
  const double dx = b.x - a.x;
  const double dy = b.y - a.y;
  const double length = std::hypot(dx, dy);
  if (length == 0.0) return std::hypot(p.x - a.x, p.y - a.y);
  return std::abs(dx * (p.y - a.y) - dy * (p.x - a.x)) / length;
}

// Douglas-Peucker split of [first, last] (explicit stack: outlines can be thousands of cells).
void split(const std::vector<cv::Point>& outline, Piece whole, double tolerance,
           std::vector<Piece>& pieces) {
  std::vector<Piece> stack{whole};
  while (!stack.empty()) {
    const Piece piece = stack.back();
    stack.pop_back();
    int worst = -1;
    double worst_distance = tolerance;
    for (int i = piece.first + 1; i < piece.last; ++i) {
      const double d =
          chord_distance(at(outline, piece.first), at(outline, piece.last), at(outline, i));
      if (d > worst_distance) {
        worst_distance = d;
        worst = i;
      }
    }
    if (worst < 0) {
      pieces.push_back(piece);
    } else {
      // Second half first on the stack's bottom so pieces come out in outline order.
      stack.push_back({worst, piece.last});
      stack.push_back({piece.first, worst});
    }
  }
}

LineSegment fit_cells(const std::vector<cv::Point>& outline, Piece piece) {
  LineFitter fitter;
  for (int i = piece.first; i <= piece.last; ++i) {
    const cv::Point& p = at(outline, i);
    fitter.add({p.x + 0.5, p.y + 0.5});
  }
  return fitter.fit();
}

double max_residual_cells(const std::vector<cv::Point>& outline, Piece piece,
                          const LineSegment& line) {
  double worst = 0.0;
  for (int i = piece.first; i <= piece.last; ++i) {
    const cv::Point& p = at(outline, i);
    worst = std::max(worst, std::abs(signed_distance(line, {p.x + 0.5, p.y + 0.5})));
  }
  return worst;
}

// Two consecutive pieces join when they run the same way (a one-cell wall's outline doubles back
// on itself along one line) and the joined piece is still straight.
bool mergeable(const std::vector<cv::Point>& outline, Piece first, Piece second, double tolerance) {
  const cv::Point d1 = at(outline, first.last) - at(outline, first.first);
  const cv::Point d2 = at(outline, second.last) - at(outline, second.first);
  if (d1.dot(d2) <= 0) return false;
  const Piece joined{first.first, second.last};
  return max_residual_cells(outline, joined, fit_cells(outline, joined)) <= tolerance;
}

// Split-and-merge over one closed outline, cut first at the cell farthest from its start.
std::vector<Piece> straight_pieces(const std::vector<cv::Point>& outline, double tolerance) {
  const int n = static_cast<int>(outline.size());
  int far = 0;
  double far_distance = -1.0;
  for (int i = 0; i < n; ++i) {
    const double d = std::hypot(outline[static_cast<std::size_t>(i)].x - outline[0].x,
                                outline[static_cast<std::size_t>(i)].y - outline[0].y);
    if (d > far_distance) {
      far_distance = d;
      far = i;
    }
  }
  std::vector<Piece> pieces;
  split(outline, {0, far}, tolerance, pieces);
  split(outline, {far, n}, tolerance, pieces);

  bool merged_any = true;
  while (merged_any && pieces.size() > 1) {
    merged_any = false;
    for (std::size_t k = 0; k + 1 < pieces.size(); ++k) {
      if (mergeable(outline, pieces[k], pieces[k + 1], tolerance)) {
        pieces[k].last = pieces[k + 1].last;
        pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(k) + 1);
        merged_any = true;
      }
    }
  }
  // The cut at index 0 is arbitrary: close it when the two ends are one straight wall.
  if (pieces.size() > 1) {
    const Piece wrapped_front{pieces.front().first + n, pieces.front().last + n};
    if (wrapped_front.last - pieces.back().first < n &&
        mergeable(outline, pieces.back(), wrapped_front, tolerance)) {
      pieces.front() = {pieces.back().first, wrapped_front.last};
      pieces.pop_back();
    }
  }
  return pieces;
}

// Whether a grid cell is known free, for outline cells given in padded image coordinates.
class FreeSideProbe {
 public:
  FreeSideProbe(const mapping::OccupancyGrid& grid, std::uint8_t free_max_value)
      : grid_(grid), free_max_value_(free_max_value) {}

  bool free_beside(const cv::Point& p, double nx, double ny) const {
    const mapping::CellIndex cell{static_cast<int>(std::lround(p.x - 1 + nx)),
                                  static_cast<int>(std::lround(p.y - 1 + ny))};
    if (!grid_.contains(cell)) return false;
    const std::uint8_t v = grid_.at(cell);
    return v != mapping::OccupancyGrid::kUnknown && v <= free_max_value_;
  }

 private:
  const mapping::OccupancyGrid& grid_;
  std::uint8_t free_max_value_;
};

// Drops end cells that are off the fitted line by more than this (cells): the turn of a corner
// that split-and-merge left on a piece (a 1-cell step sits right at the split tolerance).
constexpr double kEndTrimCells = 0.6;

Piece trimmed(const std::vector<cv::Point>& outline, Piece piece) {
  while (piece.last - piece.first >= 2) {
    const LineSegment line = fit_cells(outline, piece);
    const auto residual = [&](int i) {
      const cv::Point& p = at(outline, i);
      return std::abs(signed_distance(line, {p.x + 0.5, p.y + 0.5}));
    };
    const double head = residual(piece.first);
    const double tail = residual(piece.last);
    if (head <= kEndTrimCells && tail <= kEndTrimCells) break;
    if (head >= tail) {
      ++piece.first;
    } else {
      --piece.last;
    }
  }
  return piece;
}

// Turns one straight piece (padded image coordinates, in cells) into a wall face in the grid
// frame (metres), or reports that it does not face free space.
std::optional<LineSegment> wall_face(const std::vector<cv::Point>& outline, Piece piece,
                                     const mapping::OccupancyGrid& grid,
                                     const MapLineExtractorOptions& options,
                                     const FreeSideProbe& probe) {
  piece = trimmed(outline, piece);
  LineSegment line = fit_cells(outline, piece);
  const cv::Point& head = at(outline, piece.first);
  const cv::Point& tail = at(outline, piece.last);
  // OpenCV follows outer and hole borders in opposite senses so that, with rows as y, the
  // non-wall side is always on the left of the direction of travel. This also gives each face of
  // a one-cell wall once, as the outline passes it in both directions.
  const double left_x = -(tail.y - head.y);
  const double left_y = tail.x - head.x;
  double nx = std::cos(line.alpha_rad);
  double ny = std::sin(line.alpha_rad);
  const double outward = left_x * nx + left_y * ny > 0.0 ? 1.0 : -1.0;
  nx *= outward;
  ny *= outward;

  const int cells = piece.last - piece.first + 1;
  int free_cells = 0;
  for (int i = piece.first; i <= piece.last; ++i) {
    free_cells += probe.free_beside(at(outline, i), nx, ny) ? 1 : 0;
  }
  if (options.require_free_side &&
      static_cast<double>(free_cells) < options.min_free_fraction * cells) {
    return std::nullopt;
  }

  // Cell centres (padded coordinates) -> grid-frame metres, moved half a cell onto the face.
  const double res = grid.resolution_m();
  const double shift_m = 0.5 * res;
  line.rho_m = (line.rho_m - (std::cos(line.alpha_rad) + std::sin(line.alpha_rad))) * res +
               outward * shift_m;
  line.free_side = outward > 0.0 ? 1 : -1;
  line = normalized(line);
  const geometry::Point2D head_m{(head.x - 0.5) * res, (head.y - 0.5) * res};
  const geometry::Point2D tail_m{(tail.x - 0.5) * res, (tail.y - 0.5) * res};
  geometry::Point2D start = project_onto(line, head_m);
  geometry::Point2D end = project_onto(line, tail_m);
  const double length_m = std::hypot(end.x - start.x, end.y - start.y);
  if (length_m + res < options.min_length_m) return std::nullopt;
  if (length_m > 0.0) {
    // The face spans the end cells fully.
    const double ux = (end.x - start.x) / length_m * 0.5 * res;
    const double uy = (end.y - start.y) / length_m * 0.5 * res;
    start = {start.x - ux, start.y - uy};
    end = {end.x + ux, end.y + uy};
  }
  line.start = start;
  line.end = end;
  line.has_endpoints = true;
  line.point_count = cells;

  std::vector<geometry::Point2D> face_points_m;
  face_points_m.reserve(static_cast<std::size_t>(cells));
  for (int i = piece.first; i <= piece.last; ++i) {
    const cv::Point& p = at(outline, i);
    // The samples move onto the face too, so the residuals measure straightness only.
    face_points_m.push_back({(p.x - 0.5) * res + shift_m * nx, (p.y - 0.5) * res + shift_m * ny});
  }
  const std::vector<double> quantisation_var_m2(face_points_m.size(), res * res / 12.0);
  return with_covariance(line, face_points_m, quantisation_var_m2);
}

}  // namespace

std::vector<LineSegment> extract_map_lines(const mapping::OccupancyGrid& grid,
                                           const MapLineExtractorOptions& options) {
  if (grid.width() <= 0 || grid.height() <= 0) return {};
  cv::Mat mask = wall_mask(grid, options.occupied_min_value);
  std::vector<std::vector<cv::Point>> outlines;
  cv::findContours(mask, outlines, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);

  const FreeSideProbe probe(grid, options.free_max_value);
  const double tolerance = std::max(options.split_tolerance_cells, 0.1);
  std::vector<LineSegment> lines;
  for (const std::vector<cv::Point>& outline : outlines) {
    if (outline.size() < 2) continue;
    for (const Piece piece : straight_pieces(outline, tolerance)) {
      if (auto face = wall_face(outline, piece, grid, options, probe)) {
        lines.push_back(transform_line(grid.origin(), *face));
      }
    }
  }
  return lines;
}

}  // namespace mobot::perception
