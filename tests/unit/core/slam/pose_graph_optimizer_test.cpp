#include "core/slam/pose_graph_optimizer.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

namespace mobot::slam {
namespace {

// A 4 x 4 m square driven counter-clockwise, 4 steps of 1 m per side with a 90 deg turn at each
// corner: 16 steps back to the start.
std::vector<geometry::Pose2D> square() {
  std::vector<geometry::Pose2D> poses{{0.0, 0.0, 0.0}};
  for (int side = 0; side < 4; ++side) {
    for (int step = 0; step < 4; ++step) {
      const double turn = step == 3 ? std::numbers::pi / 2.0 : 0.0;
      poses.push_back(geometry::compose(poses.back(), {1.0, 0.0, turn}));
    }
  }
  return poses;
}

PoseGraph drifting_square(const std::vector<geometry::Pose2D>& truth) {
  PoseGraph graph;
  geometry::Pose2D dead_reckoning = truth[0];
  graph.add_node(dead_reckoning);
  for (std::size_t i = 1; i < truth.size(); ++i) {
    geometry::Pose2D step = geometry::compose(geometry::inverse(truth[i - 1]), truth[i]);
    step.theta += 0.03;  // heading drift
    step.x *= 1.02;      // scale error
    dead_reckoning = geometry::compose(dead_reckoning, step);
    graph.add_node(dead_reckoning);
    PoseGraphEdge edge;
    edge.from = i - 1;
    edge.to = i;
    edge.relative = step;
    edge.information = Eigen::Vector3d(100.0, 100.0, 400.0).asDiagonal();
    graph.add_edge(edge);
  }
  return graph;
}

void add_closure(PoseGraph& graph, const std::vector<geometry::Pose2D>& truth, std::size_t from,
                 std::size_t to, const geometry::Pose2D& error = {}, double information = 1e4) {
  PoseGraphEdge loop;
  loop.from = from;
  loop.to = to;
  loop.relative =
      geometry::compose(geometry::compose(geometry::inverse(truth[from]), truth[to]), error);
  loop.information = Eigen::Vector3d(information, information, information).asDiagonal();
  loop.kind = EdgeKind::kLoop;
  graph.add_edge(loop);
}

double max_position_error(const PoseGraph& graph, const std::vector<geometry::Pose2D>& truth) {
  double worst = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    worst = std::max(worst, std::hypot(graph.pose(i).x - truth[i].x, graph.pose(i).y - truth[i].y));
  }
  return worst;
}

TEST(PoseGraphOptimizer, ALoopClosureRestoresTheSquare) {
  const auto truth = square();
  PoseGraph graph = drifting_square(truth);
  const double before = max_position_error(graph, truth);
  EXPECT_GT(before, 0.5);
  add_closure(graph, truth, 0, truth.size() - 1);
  add_closure(graph, truth, 4, 8);
  add_closure(graph, truth, 8, 12);
  const OptimizationReport report = optimize_pose_graph(graph);
  EXPECT_LT(report.final_cost, report.initial_cost);
  EXPECT_LT(max_position_error(graph, truth), 0.1);
  // The first node is fixed: it anchors the map frame.
  EXPECT_EQ(graph.pose(0), truth[0]);
}

TEST(PoseGraphOptimizer, TheHuberKernelLimitsAWrongClosure) {
  // Odometry says node 1 is 1 m ahead, a wrong closure says 2.5 m, both with information 100.
  // Least squares splits the difference (1.75 m); with Huber (delta 2) the closure pulls with a
  // constant force: 200 (x - 1) = 2 delta sqrt(100) gives x = 1.2 m.
  auto make = [] {
    PoseGraph graph;
    graph.add_node({});
    graph.add_node({1.0, 0.0, 0.0});
    PoseGraphEdge odometry;
    odometry.from = 0;
    odometry.to = 1;
    odometry.relative = {1.0, 0.0, 0.0};
    odometry.information = 100.0 * Eigen::Matrix3d::Identity();
    odometry.kind = EdgeKind::kOdometry;
    graph.add_edge(odometry);
    PoseGraphEdge loop = odometry;
    loop.relative = {2.5, 0.0, 0.0};
    loop.kind = EdgeKind::kLoop;
    graph.add_edge(loop);
    return graph;
  };
  PoseGraph plain = make();
  PoseGraph robust = make();
  PoseGraphOptimizerOptions quadratic;
  quadratic.loop_huber_delta = 0.0;
  optimize_pose_graph(plain, quadratic);
  optimize_pose_graph(robust);
  EXPECT_NEAR(plain.pose(1).x, 1.75, 1e-3);
  EXPECT_NEAR(robust.pose(1).x, 1.2, 1e-2);
}

TEST(PoseGraphOptimizer, LeavesTrivialGraphsAloneAndRejectsBadOptions) {
  PoseGraph single;
  single.add_node({1.0, 2.0, 3.0});
  EXPECT_EQ(optimize_pose_graph(single).iterations, 0);
  EXPECT_EQ(single.pose(0), (geometry::Pose2D{1.0, 2.0, 3.0}));
  PoseGraphOptimizerOptions bad;
  bad.max_iterations = -1;
  EXPECT_THROW(optimize_pose_graph(single, bad), std::invalid_argument);
  bad = {};
  bad.loop_huber_delta = std::nan("");
  EXPECT_THROW(optimize_pose_graph(single, bad), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::slam
