#include "server/stages/estimate_stage.h"

#include <stdexcept>

#include "api/prometheus_text.h"
#include "core/estimation/particle_filter/particle_filter.h"
#include "core/perception/map_line_extractor.h"

namespace mobot::server {

Eigen::Matrix3d placement_covariance() {
  return Eigen::Matrix3d(Eigen::Vector3d(1e-4, 1e-4, 3e-4).asDiagonal());
}

EstimateStage::EstimateStage(const estimation::OdometryParams& odometry, EstimatorMaker make,
                             const std::string& method, const geometry::Pose2D& start)
    : odometry_(odometry, start), make_(std::move(make)), selected_(method) {
  estimator_ = make_(method);
  if (!estimator_) throw std::invalid_argument("no estimator is called '" + method + "'");
  estimator_->reset(start, placement_covariance());
}

bool EstimateStage::select(const std::string& method, TickContext& context) {
  // The method already running stays as it is (a PUT of the same value changes nothing): a new
  // particle filter would restart its recovery averages from the next scan, and a robot
  // kidnapped just then would never be searched for.
  if (method == selected_ && estimator_->name() == method) return true;
  auto next = make_(method);
  if (!next) return false;
  selected_ = method;
  hand_over(std::move(next), context);
  return true;
}

void EstimateStage::substitute(std::unique_ptr<estimation::PoseEstimator> estimator,
                               TickContext& context) {
  hand_over(std::move(estimator), context);
}

bool EstimateStage::start_global_localization(TickContext& context) {
  if (!estimator_->start_global_localization()) return false;
  write(context);
  return true;
}

void EstimateStage::restore_selected(TickContext& context) {
  if (auto next = make_(selected_)) hand_over(std::move(next), context);
}

void EstimateStage::hand_over(std::unique_ptr<estimation::PoseEstimator> next,
                              TickContext& context) {
  next->set_map(map_);
  next->reset(estimator_->pose(), estimator_->covariance());
  estimator_ = std::move(next);
  write(context);
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
  publish_particles(context);
}

void EstimateStage::publish_particles(TickContext& context) {
  if (!particles_schedule_.due(context.now_s)) return;
  particles_schedule_.taken(context.now_s);
  std::vector<estimation::WeightedPose> particles = estimator_->particles(kMaxParticlesShown);
  if (particles.empty()) return;
  const std::size_t total = estimator_->particle_count();
  context.bus->particles.publish({context.now_s, std::move(particles), total});
}

void EstimateStage::write(TickContext& context) {
  context.pose = estimator_->pose();
  context.covariance = estimator_->covariance();
  context.odometry = odometry_.odometry();
  context.distance_m = distance_before_reset_m_ + odometry_.travelled_m();
  context.localization_method = estimator_->method();
  context.localization_converged = estimator_->converged();
  const bool changed = converged_ && *converged_ != context.localization_converged;
  converged_ = context.localization_converged;
  if (changed) {
    context.event("localization",
                  {{"method", context.localization_method}, {"converged", *converged_}});
  }
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
  if (!map.grid->cells().empty()) {
    const estimation::ParticleFilterMap field = estimation::prepare_particle_filter_map(*map.grid);
    model->likelihood_field = field.field;
    model->free_space = field.free_space;
  }
  prepared_map_ = std::move(model);
}

void EstimateStage::apply_map(const ActiveMap&, TickContext&) {
  map_ = std::move(prepared_map_);
  estimator_->set_map(map_);
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
