#include "server/stages/mapping_stage.h"

namespace mobot::server {

void MappingStage::step(TickContext& context) {
  context.mapping = active();
  if (!worker_) return;
  if (auto update = worker_->take_map_update()) {
    context.bus->map_tiles.publish(
        {context.now_s, std::move(update->grid), std::move(update->tiles)});
  }
}

std::shared_ptr<SlamWorker> MappingStage::start(TickContext& context) {
  worker_ = std::make_shared<SlamWorker>(options_, context.pose, context.pose);
  session_.store(std::make_shared<const MappingSession>(MappingSession{worker_, context.now_s}));
  context.mapping = true;
  return worker_;
}

std::shared_ptr<SlamWorker> MappingStage::end(TickContext& context) {
  std::shared_ptr<SlamWorker> worker = std::move(worker_);
  worker_.reset();
  session_.store(nullptr);
  context.mapping = false;
  return worker;
}

}  // namespace mobot::server
