#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "core/estimation/pose_estimator.h"
#include "core/estimation/wheel_odometry.h"
#include "core/timing/rate_schedule.h"
#include "server/map_listener.h"
#include "server/stage.h"

namespace mobot::server {

// Localization: wheel odometry (the odom frame) and the configured pose estimator (the map
// frame), fed with this tick's readings. Commands run on the control loop between ticks.
class EstimateStage final : public Stage, public MapListener {
 public:
  // Makes the estimator registered under a name; null for an unknown name.
  using EstimatorMaker =
      std::function<std::unique_ptr<estimation::PoseEstimator>(std::string_view name)>;

  // Starts with the estimator `method` (which `make` must know).
  EstimateStage(const estimation::OdometryParams& odometry, EstimatorMaker make,
                const std::string& method, const geometry::Pose2D& start);

  std::string_view name() const override { return "estimate"; }
  void step(TickContext& context) override;

  // Re-initialises both frames at `pose` (the robot was put there: a sim reset).
  void reset(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance, TickContext& context);
  // Re-initialises the map-frame estimate only (the operator's initial pose).
  void set_pose(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance,
                TickContext& context);
  void prepare_map(const ActiveMap& map) override;
  void apply_map(const ActiveMap& map, TickContext& context) override;

  // Switches to the registered estimator `method`, starting from the current estimate and with the
  // active map; the method already running is kept as it is. False (nothing changed) for an
  // unknown name.
  bool select(const std::string& method, TickContext& context);
  // Hands the estimate to `estimator` (SLAM while mapping) until restore_selected(); the selected
  // method stays what select() chose.
  void substitute(std::unique_ptr<estimation::PoseEstimator> estimator, TickContext& context);
  // Back to the selected method, from the current estimate.
  void restore_selected(TickContext& context);
  const std::string& selected() const { return selected_; }
  // Spreads the estimator's belief over the active map's free space; false when it cannot.
  bool start_global_localization(TickContext& context);
  bool has_map() const { return map_ && map_->grid && map_->grid->width() > 0; }

  const estimation::PoseEstimator& estimator() const { return *estimator_; }
  estimation::PoseEstimator& estimator() { return *estimator_; }
  std::string metrics_text() const;

 private:
  void write(TickContext& context);
  void publish_particles(TickContext& context);
  // At most this many particles go to the display (a weighted sample of the belief).
  static constexpr std::size_t kMaxParticlesShown = 2000;
  void hand_over(std::unique_ptr<estimation::PoseEstimator> next, TickContext& context);

  estimation::WheelOdometry odometry_;
  EstimatorMaker make_;
  std::string selected_;
  std::unique_ptr<estimation::PoseEstimator> estimator_;
  std::shared_ptr<const estimation::MapModel> map_;  // the active map, for the next estimator
  std::optional<bool> converged_;
  // The particles topic's pace (docs/api.md): a display, not a log.
  timing::RateSchedule particles_schedule_{0.2};  // as last written: a change is an event
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
