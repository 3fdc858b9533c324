#include "core/planning/dubins_path.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/numeric/constants.h"

namespace mobot::planning {
namespace {

// Into [0, 2 pi). A turn that rounding left a hair below a full circle is no turn: no shortest
// path turns a full circle, and keeping it would add a loop.
double turn_angle(double angle_rad) {
  double wrapped = std::fmod(angle_rad, kTwoPi);
  if (wrapped < 0.0) wrapped += kTwoPi;
  return wrapped > kTwoPi - 1e-10 ? 0.0 : wrapped;
}

// Rounding may leave a zero-length straight's square, or a tangent circle's cosine, a hair on the
// wrong side: accept those, or the exact quarter turn would be missed for a loop.
constexpr double kSlack = 1e-10;

enum class Word { kLsl, kRsr, kLsr, kRsl, kRlr, kLrl };

// Per word: the turning direction of each piece (+1 left, 0 straight, -1 right).
constexpr std::array<std::array<int, 3>, 6> kDirections{
    {{1, 0, 1}, {-1, 0, -1}, {1, 0, -1}, {-1, 0, 1}, {-1, 1, -1}, {1, -1, 1}}};

// The three piece lengths of a word in units of the radius (angles for the turns), for the goal
// at normalised distance d with the headings alpha and beta measured from the start-goal line;
// nullopt when the word cannot join them.
std::optional<std::array<double, 3>> word_lengths(Word word, double d, double alpha, double beta) {
  const double sa = std::sin(alpha);
  const double sb = std::sin(beta);
  const double ca = std::cos(alpha);
  const double cb = std::cos(beta);
  const double c_ab = std::cos(alpha - beta);
  switch (word) {
    case Word::kLsl: {
      const double p_sq = 2.0 + d * d - 2.0 * c_ab + 2.0 * d * (sa - sb);
      if (p_sq < -kSlack) return std::nullopt;
      const double tmp = std::atan2(cb - ca, d + sa - sb);
      return std::array{turn_angle(tmp - alpha), std::sqrt(std::max(p_sq, 0.0)),
                        turn_angle(beta - tmp)};
    }
    case Word::kRsr: {
      const double p_sq = 2.0 + d * d - 2.0 * c_ab + 2.0 * d * (sb - sa);
      if (p_sq < -kSlack) return std::nullopt;
      const double tmp = std::atan2(ca - cb, d - sa + sb);
      return std::array{turn_angle(alpha - tmp), std::sqrt(std::max(p_sq, 0.0)),
                        turn_angle(tmp - beta)};
    }
    case Word::kLsr: {
      const double p_sq = -2.0 + d * d + 2.0 * c_ab + 2.0 * d * (sa + sb);
      if (p_sq < -kSlack) return std::nullopt;
      const double p = std::sqrt(std::max(p_sq, 0.0));
      const double tmp = std::atan2(-ca - cb, d + sa + sb) - std::atan2(-2.0, p);
      return std::array{turn_angle(tmp - alpha), p, turn_angle(tmp - beta)};
    }
    case Word::kRsl: {
      const double p_sq = -2.0 + d * d + 2.0 * c_ab - 2.0 * d * (sa + sb);
      if (p_sq < -kSlack) return std::nullopt;
      const double p = std::sqrt(std::max(p_sq, 0.0));
      const double tmp = std::atan2(ca + cb, d - sa - sb) - std::atan2(2.0, p);
      return std::array{turn_angle(alpha - tmp), p, turn_angle(beta - tmp)};
    }
    case Word::kRlr: {
      const double c = (6.0 - d * d + 2.0 * c_ab + 2.0 * d * (sa - sb)) / 8.0;
      if (std::abs(c) > 1.0 + kSlack) return std::nullopt;
      const double phi = std::atan2(ca - cb, d - sa + sb);
      const double p = kTwoPi - std::acos(std::clamp(c, -1.0, 1.0));  // (pi, 2 pi]
      const double t = turn_angle(alpha - phi + p / 2.0);
      return std::array{t, p, turn_angle(alpha - beta - t + p)};
    }
    case Word::kLrl: {
      const double c = (6.0 - d * d + 2.0 * c_ab + 2.0 * d * (sb - sa)) / 8.0;
      if (std::abs(c) > 1.0 + kSlack) return std::nullopt;
      const double phi = std::atan2(ca - cb, d + sa - sb);
      const double p = kTwoPi - std::acos(std::clamp(c, -1.0, 1.0));  // (pi, 2 pi]
      const double t = turn_angle(-alpha - phi + p / 2.0);
      return std::array{t, p, turn_angle(beta - alpha - t + p)};
    }
  }
  return std::nullopt;
}

// The turn-then-straight path to `point` turning left; nullopt when the point lies inside the
// left turning circle.
std::optional<DubinsPath> left_then_straight(const geometry::Pose2D& start, geometry::Point2D point,
                                             double radius_m, double side) {
  // In the start's frame, mirrored for a right turn (side -1) so the turn is always to the left.
  const double c = std::cos(start.theta);
  const double s = std::sin(start.theta);
  const double dx = point.x - start.x;
  const double dy = point.y - start.y;
  const double x = c * dx + s * dy;
  const double y = side * (-s * dx + c * dy);
  // From the turning centre (0, R) the point is at distance d; the straight is the tangent from
  // the circle to the point, of length sqrt(d^2 - R^2), and the turn phi satisfies
  // point - centre = straight * (cos phi, sin phi) + R * (sin phi, -cos phi).
  const double cy = y - radius_m;
  const double d_sq = x * x + cy * cy;
  const double straight_sq = d_sq - radius_m * radius_m;
  if (straight_sq < 0.0) return std::nullopt;
  const double straight_m = std::sqrt(straight_sq);
  const double phi = turn_angle(std::atan2(cy, x) + std::atan2(radius_m, straight_m));
  const std::array<DubinsPath::Piece, 2> pieces{
      {{side / radius_m, phi * radius_m}, {0.0, straight_m}}};
  return DubinsPath(start, pieces);
}

}  // namespace

DubinsPath::DubinsPath(const geometry::Pose2D& start, std::span<const Piece> pieces)
    : start_(start), count_(pieces.size()) {
  if (pieces.size() > pieces_.size()) throw std::invalid_argument("a path has at most 3 pieces");
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (!(pieces[i].length_m >= 0.0)) throw std::invalid_argument("negative piece length");
    pieces_[i] = pieces[i];
  }
}

double DubinsPath::length_m() const {
  double total = 0.0;
  for (const Piece& piece : pieces()) total += piece.length_m;
  return total;
}

double DubinsPath::max_curvature_1pm() const {
  double worst = 0.0;
  for (const Piece& piece : pieces()) {
    if (piece.length_m > 0.0) worst = std::max(worst, std::abs(piece.curvature_1pm));
  }
  return worst;
}

geometry::Pose2D DubinsPath::pose_at(double s_m) const {
  geometry::Pose2D pose = start_;
  double left_m = std::max(s_m, 0.0);
  for (const Piece& piece : pieces()) {
    const double step = std::min(left_m, piece.length_m);
    pose = advance(pose, piece.curvature_1pm, step);
    left_m -= step;
    if (left_m <= 0.0) break;
  }
  return pose;
}

geometry::Pose2D advance(const geometry::Pose2D& pose, double curvature_1pm, double length_m) {
  const double turn = curvature_1pm * length_m;
  // The chord: length 2 sin(turn / 2) / curvature along the mean heading; written with sinc so a
  // straight (curvature 0) and a nearly straight arc take the same, exact, branch.
  const double half = 0.5 * turn;
  const double chord = std::abs(half) < 1e-6 ? length_m * (1.0 - half * half / 6.0)
                                             : length_m * std::sin(half) / half;
  const double mean = pose.theta + half;
  return {pose.x + chord * std::cos(mean), pose.y + chord * std::sin(mean), pose.theta + turn};
}

DubinsPath shortest_dubins_path(const geometry::Pose2D& start, const geometry::Pose2D& goal,
                                double radius_m) {
  const double dx = goal.x - start.x;
  const double dy = goal.y - start.y;
  const double d = std::hypot(dx, dy) / radius_m;
  const double line = d > 0.0 ? std::atan2(dy, dx) : 0.0;
  const double alpha = turn_angle(start.theta - line);
  const double beta = turn_angle(goal.theta - line);
  constexpr std::array kWords{Word::kLsl, Word::kRsr, Word::kLsr,
                              Word::kRsl, Word::kRlr, Word::kLrl};
  double best_length = std::numeric_limits<double>::infinity();
  std::array<DubinsPath::Piece, 3> best{};
  for (std::size_t w = 0; w < kWords.size(); ++w) {
    const auto lengths = word_lengths(kWords[w], d, alpha, beta);
    if (!lengths) continue;
    const double total = (*lengths)[0] + (*lengths)[1] + (*lengths)[2];
    if (total >= best_length) continue;
    best_length = total;
    for (std::size_t i = 0; i < 3; ++i) {
      best[i] = {kDirections[w][i] / radius_m, (*lengths)[i] * radius_m};
    }
  }
  return DubinsPath(start, best);
}

DubinsPath turn_then_straight_to_point(const geometry::Pose2D& start, geometry::Point2D point,
                                       double radius_m) {
  const auto left = left_then_straight(start, point, radius_m, 1.0);
  const auto right = left_then_straight(start, point, radius_m, -1.0);
  if (!left) return *right;  // the point cannot lie inside both circles: they only touch
  if (!right) return *left;
  return left->length_m() <= right->length_m() ? *left : *right;
}

std::optional<DubinsPath> arc_to_point(const geometry::Pose2D& start, geometry::Point2D point,
                                       double min_radius_m) {
  const double c = std::cos(start.theta);
  const double s = std::sin(start.theta);
  const double dx = point.x - start.x;
  const double dy = point.y - start.y;
  const double x = c * dx + s * dy;
  const double y = -s * dx + c * dy;
  if (!(x > 0.0)) return std::nullopt;
  const double d_sq = x * x + y * y;
  const double curvature = 2.0 * y / d_sq;  // the circle tangent to the heading through the point
  if (std::abs(curvature) * min_radius_m > 1.0) return std::nullopt;
  // The arc turns by twice the angle at which the point is seen: its chord is the segment.
  const double half = std::atan2(y, x);
  const double chord = std::sqrt(d_sq);
  const double length = std::abs(half) < 1e-6 ? chord : chord * half / std::sin(half);
  const std::array<DubinsPath::Piece, 1> piece{{{curvature, length}}};
  return DubinsPath(start, piece);
}

}  // namespace mobot::planning
