#include "server/stages/sweep_stage.h"

namespace mobot::server {

SweepStage::SweepStage(drivers::TiltLaserDriver& tilt, Listener listener)
    : tilt_(tilt), listener_(std::move(listener)) {}

bool SweepStage::start(std::int64_t id, const perception::SweepMode& mode, TickContext& context) {
  if (sweep_) return false;
  sweep_.emplace(Active{id, mode, context.now_s, 0, {}, {}});
  // A 42 s sweep at 0.25 deg holds 100 scans of 721 beams.
  sweep_->cloud.reserve(static_cast<std::size_t>(mode.scans) *
                        (static_cast<std::size_t>(180.0 / mode.step_deg) + 1));
  tilt_.start(mode, context.now_s);
  context.sweep = SweepProgress{id, 0, mode.scans, 0};
  return true;
}

void SweepStage::step(TickContext& context) {
  if (!sweep_) return;
  while (sweep_->scans_done < sweep_->mode.scans) {
    const auto scan = tilt_.poll(context.now_s);
    if (!scan) break;
    take_scan(*scan, context);
  }
  context.sweep =
      SweepProgress{sweep_->id, sweep_->scans_done, sweep_->mode.scans, sweep_->cloud.size()};
  if (sweep_->scans_done >= sweep_->mode.scans) finish(std::nullopt, context);
}

void SweepStage::take_scan(const msgs::TiltScan& scan, TickContext& context) {
  Active& sweep = *sweep_;
  if (sweep.scans_done == 0) {
    const geometry::Pose2D sensor = geometry::compose(context.pose, scan.sensor_in_base);
    sweep.origin_in_map = {sensor.x, sensor.y};
  }
  const std::size_t first = sweep.cloud.size();
  perception::append_scan(scan, context.pose, sweep.cloud);
  ++sweep.scans_done;
  context.bus->cloud.publish(
      {context.now_s,
       {static_cast<std::uint32_t>(sweep.id), static_cast<std::uint32_t>(first),
        sweep.scans_done == sweep.mode.scans, static_cast<std::uint32_t>(sweep.scans_done),
        static_cast<std::uint32_t>(sweep.mode.scans)},
       std::span<const perception::CloudPoint>(sweep.cloud).subspan(first)});
}

void SweepStage::abort(const std::string& reason, TickContext& context) {
  if (!sweep_) return;
  tilt_.stop();
  finish(reason, context);
}

void SweepStage::finish(std::optional<std::string> failure, TickContext& context) {
  SweepOutcome outcome{
      sweep_->id,    std::move(failure), {}, sweep_->origin_in_map, sweep_->started_s,
      context.now_s, map_generation_};
  if (!outcome.failure) outcome.cloud = std::move(sweep_->cloud);
  sweep_.reset();
  context.sweep.reset();
  if (listener_) listener_(std::move(outcome));
}

void SweepStage::apply_map(const ActiveMap& map, TickContext& context) {
  // The cloud of a running sweep belongs to the map it started on.
  abort("map_changed", context);
  map_generation_ = map.generation;
}

}  // namespace mobot::server
