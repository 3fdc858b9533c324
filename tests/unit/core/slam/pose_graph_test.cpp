#include "core/slam/pose_graph.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace mobot::slam {
namespace {

TEST(PoseGraph, ResidualIsZeroWhenThePosesAgree) {
  const geometry::Pose2D a{1.0, 2.0, 0.5};
  const geometry::Pose2D relative{0.7, -0.2, 0.3};
  const geometry::Pose2D b = geometry::compose(a, relative);
  EXPECT_LT(edge_residual(a, b, relative).norm(), 1e-12);
  const Eigen::Vector3d off = edge_residual(a, geometry::compose(b, {0.1, 0.0, 0.0}), relative);
  EXPECT_NEAR(off.x(), 0.1, 1e-12);
  EXPECT_NEAR(off.z(), 0.0, 1e-12);
  // Wrapped: a full turn more is no error.
  EXPECT_NEAR(edge_residual(a, {b.x, b.y, b.theta + 2.0 * std::acos(-1.0)}, relative).norm(), 0.0,
              1e-9);
}

TEST(PoseGraph, ValidatesNodesAndEdges) {
  PoseGraph graph;
  EXPECT_THROW(graph.add_node({std::nan(""), 0.0, 0.0}), std::invalid_argument);
  EXPECT_EQ(graph.add_node({}), 0U);
  EXPECT_EQ(graph.add_node({1.0, 0.0, 0.0}), 1U);
  PoseGraphEdge edge;
  edge.from = 0;
  edge.to = 1;
  edge.relative = {1.0, 0.0, 0.0};
  EXPECT_NO_THROW(graph.add_edge(edge));
  PoseGraphEdge bad = edge;
  bad.to = 2;
  EXPECT_THROW(graph.add_edge(bad), std::invalid_argument);
  bad = edge;
  bad.to = 0;
  EXPECT_THROW(graph.add_edge(bad), std::invalid_argument);
  bad = edge;
  bad.information(0, 0) = -1.0;
  EXPECT_THROW(graph.add_edge(bad), std::invalid_argument);
  bad = edge;
  bad.information(0, 1) = 0.5;  // asymmetric
  EXPECT_THROW(graph.add_edge(bad), std::invalid_argument);
  bad = edge;
  bad.relative.theta = std::nan("");
  EXPECT_THROW(graph.add_edge(bad), std::invalid_argument);
  EXPECT_EQ(graph.edges().size(), 1U);
  EXPECT_THROW(graph.set_poses({{}}), std::invalid_argument);
  EXPECT_THROW(graph.set_poses({{}, {std::nan(""), 0, 0}}), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::slam
