#include "server/stages/estimate_stage.h"

#include "api/prometheus_text.h"
#include "core/perception/map_line_extractor.h"

namespace mobot::server {

Eigen::Matrix3d placement_covariance() {
  return Eigen::Matrix3d(Eigen::Vector3d(1e-4, 1e-4, 3e-4).asDiagonal());
}

EstimateStage::EstimateStage(const estimation::OdometryParams& odometry,
                             std::unique_ptr<estimation::PoseEstimator> estimator,
                             const geometry::Pose2D& start)
    : odometry_(odometry, start), estimator_(std::move(estimator)) {
  estimator_->reset(start, placement_covariance());
}

void EstimateStage::step(TickContext& context) {
  estimation::EstimatorInputs inputs;
  inputs.stamp_s = context.now_s;
  if (context.encoders) {
    odometry_.update(*context.encoders);
    inputs.travel = &odometry_.last_travel();
    inputs.track_m = odometry_.params().track_m;
  }
  if (context.scan) inputs.scan = &*context.scan;
  if (context.compass) inputs.compass = &*context.compass;
  if (context.bearings) inputs.bearings = &*context.bearings;
  estimator_->update(inputs);
  const estimation::EstimatorCounters counters = estimator_->counters();
  scan_updates_.store(counters.scan_updates, std::memory_order_relaxed);
  features_matched_.store(counters.features_matched, std::memory_order_relaxed);
  rejected_updates_.store(counters.rejected_updates, std::memory_order_relaxed);
  write(context);
}

void EstimateStage::write(TickContext& context) const {
  context.pose = estimator_->pose();
  context.covariance = estimator_->covariance();
  context.odometry = odometry_.odometry();
  context.distance_m = distance_before_reset_m_ + odometry_.travelled_m();
  context.localization_method = estimator_->method();
}

void EstimateStage::reset(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance,
                          TickContext& context) {
  distance_before_reset_m_ += odometry_.travelled_m();
  odometry_ = estimation::WheelOdometry(odometry_.params(), pose);
  estimator_->reset(pose, covariance);
  write(context);
}

void EstimateStage::set_pose(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance,
                             TickContext& context) {
  estimator_->reset(pose, covariance);
  write(context);
}

void EstimateStage::prepare_map(const ActiveMap& map) {
  auto model = std::make_shared<estimation::MapModel>();
  model->grid = map.grid;
  model->wall_lines = perception::extract_map_lines(*map.grid);
  prepared_map_ = std::move(model);
}

void EstimateStage::apply_map(const ActiveMap&, TickContext&) {
  estimator_->set_map(std::move(prepared_map_));
}

std::string EstimateStage::metrics_text() const {
  std::string out;
  api::append_metric(out, "mobot_localization_line_updates_total", "counter",
                     "Scans fused as line features.", static_cast<double>(scan_updates_.load()));
  api::append_metric(out, "mobot_localization_lines_matched_total", "counter",
                     "Scan lines matched to map lines.",
                     static_cast<double>(features_matched_.load()));
  api::append_metric(out, "mobot_localization_rejected_updates_total", "counter",
                     "EKF updates refused (gate, NaN).",
                     static_cast<double>(rejected_updates_.load()));
  return out;
}

}  // namespace mobot::server
