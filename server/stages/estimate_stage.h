#pragma once

#include <atomic>
#include <memory>

#include "core/estimation/pose_estimator.h"
#include "core/estimation/wheel_odometry.h"
#include "server/map_listener.h"
#include "server/stage.h"

namespace mobot::server {

// Localization: wheel odometry (the odom frame) and the configured pose estimator (the map
// frame), fed with this tick's readings. Commands run on the control loop between ticks.
class EstimateStage final : public Stage, public MapListener {
 public:
  EstimateStage(const estimation::OdometryParams& odometry,
                std::unique_ptr<estimation::PoseEstimator> estimator,
                const geometry::Pose2D& start);

  std::string_view name() const override { return "estimate"; }
  void step(TickContext& context) override;

  // Re-initialises both frames at `pose` (the robot was put there: a sim reset).
  void reset(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance, TickContext& context);
  // Re-initialises the map-frame estimate only (the operator's initial pose).
  void set_pose(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance,
                TickContext& context);
  void prepare_map(const ActiveMap& map) override;
  void apply_map(const ActiveMap& map, TickContext& context) override;

  const estimation::PoseEstimator& estimator() const { return *estimator_; }
  std::string metrics_text() const;

 private:
  void write(TickContext& context) const;

  estimation::WheelOdometry odometry_;
  std::unique_ptr<estimation::PoseEstimator> estimator_;
  double distance_before_reset_m_ = 0.0;
  std::shared_ptr<const estimation::MapModel> prepared_map_;
  // Copies for metrics_text(), which other threads call.
  std::atomic<std::uint64_t> scan_updates_{0};
  std::atomic<std::uint64_t> features_matched_{0};
  std::atomic<std::uint64_t> rejected_updates_{0};
};

// How sure anybody is of a pose set by hand: 1 cm and 1 degree; a zero covariance would claim a
// certainty no sensor has.
Eigen::Matrix3d placement_covariance();

}  // namespace mobot::server
