#include "server/services/map_catalog.h"

#include <optional>

#include "server/wall_clock.h"

#include "core/costmap/keepout_layer.h"
#include "core/geometry/simple_polygon.h"

#include <boost/asio/post.hpp>
#include <chrono>

namespace mobot::server {
namespace {

api::MapInfo to_api(const db::MapMeta& meta) {
  return {meta.id,           meta.name,   meta.width,          meta.height,
          meta.resolution_m, meta.origin, meta.created_unix_s, meta.active};
}

api::DomainError unknown_map() {
  return {api::ErrorKind::kNotFound, "unknown_map", "no map with this id"};
}

}  // namespace

MapCatalog::MapCatalog(db::MapStore& maps, db::ZoneStore& zones, Runtime& runtime,
                       std::vector<MapListener*> listeners)
    : maps_(maps), zones_(zones), runtime_(runtime), listeners_(std::move(listeners)) {}

MapCatalog::~MapCatalog() { worker_.join(); }

std::vector<api::MapInfo> MapCatalog::list_maps() const {
  std::vector<api::MapInfo> out;
  for (const auto& meta : maps_.list()) out.push_back(to_api(meta));
  return out;
}

std::optional<api::MapInfo> MapCatalog::map_info(std::int64_t id) const {
  const auto meta = maps_.meta(id);
  if (!meta) return std::nullopt;
  return to_api(*meta);
}

std::optional<mapping::OccupancyGrid> MapCatalog::map_grid(std::int64_t id) const {
  return maps_.grid(id);
}

std::int64_t MapCatalog::import_map(const std::string& name, const mapping::OccupancyGrid& grid) {
  return maps_.insert(name, grid, unix_now_s());
}

void MapCatalog::switch_to(std::int64_t id, std::function<void()> done) {
  auto grid = maps_.grid(id);
  if (!grid) return;
  const ActiveMap map{id, ++generation_,
                      std::make_shared<const mapping::OccupancyGrid>(std::move(*grid)),
                      std::make_shared<const std::vector<mapping::KeepoutZone>>(
                          zones_.list(id).value_or(std::vector<mapping::KeepoutZone>{}))};
  for (auto* listener : listeners_) listener->prepare_map(map);
  runtime_.post([this, map, done = std::move(done)](TickContext& context) {
    for (auto* listener : listeners_) listener->apply_map(map, context);
    context.bus->map.publish({context.now_s, map.grid, map.id});
    if (done) context.then(done);
  });
}

void MapCatalog::activate_map(std::int64_t id, api::Completion<api::MapInfo> done) {
  boost::asio::post(worker_, [this, id, done = std::move(done)]() mutable {
    std::lock_guard lock(mutex_);
    if (!maps_.activate(id)) return done(unknown_map());
    const auto info = map_info(id);
    switch_to(id, [done = std::move(done), info]() mutable { done(*info); });
  });
}

void MapCatalog::activate_stored_now() {
  std::lock_guard lock(mutex_);
  if (const auto id = maps_.active_id()) switch_to(*id, {});
}

void MapCatalog::reactivate(api::Completion<api::Done> done) {
  boost::asio::post(worker_, [this, done = std::move(done)]() mutable {
    std::lock_guard lock(mutex_);
    const auto id = maps_.active_id();
    if (!id) return done(api::Done{});
    switch_to(*id, [done = std::move(done)]() mutable { done(api::Done{}); });
  });
}

void MapCatalog::ensure_named_map(const std::string& name, const mapping::OccupancyGrid& floor,
                                  Activation activation) {
  std::lock_guard lock(mutex_);
  std::optional<std::int64_t> id;
  for (const auto& meta : maps_.list()) {
    if (meta.name == name) id = meta.id;
  }
  if (!id) id = maps_.insert(name, floor, unix_now_s());
  if (activation == Activation::kAlways || !maps_.active_id()) maps_.activate(*id);
}

void MapCatalog::delete_map(std::int64_t id) {
  std::lock_guard lock(mutex_);
  switch (maps_.remove(id)) {
    case db::MapStore::RemoveResult::kRemoved:
      return;
    case db::MapStore::RemoveResult::kNotFound:
      throw api::DomainException(unknown_map());
    case db::MapStore::RemoveResult::kActive:
      throw api::DomainException(api::ErrorKind::kConflict, "map_active",
                                 "the active map cannot be deleted: activate another");
  }
}

}  // namespace mobot::server

namespace mobot::server {

std::optional<std::vector<mapping::KeepoutZone>> MapCatalog::list_zones(std::int64_t map_id) const {
  return zones_.list(map_id);
}

void MapCatalog::refresh_if_active(std::int64_t map_id, std::function<void()> done) {
  if (maps_.active_id() == map_id) return switch_to(map_id, std::move(done));
  done();
}

void MapCatalog::add_zone(std::int64_t map_id, const std::string& name,
                          const std::vector<geometry::Point2D>& polygon,
                          api::Completion<std::int64_t> done) {
  if (const auto why = geometry::SimplePolygon::error(polygon)) {
    return done(api::DomainError{api::ErrorKind::kInvalid, "invalid_polygon", *why});
  }
  boost::asio::post(worker_, [this, map_id, name, polygon, done = std::move(done)]() mutable {
    std::lock_guard lock(mutex_);
    const auto existing = zones_.list(map_id);
    if (!existing) return done(unknown_map());
    // The keep-out layer rasterises at most this many: one more would make the map unusable.
    const std::size_t limit = costmap::KeepoutLayerOptions{}.max_zones;
    if (existing->size() >= limit) {
      return done(api::DomainError{
          api::ErrorKind::kConflict, "too_many_zones",
          "a map holds at most " + std::to_string(limit) + " keep-out zones: delete one first"});
    }
    const auto id = zones_.insert(map_id, name, polygon, unix_now_s());
    if (!id) return done(unknown_map());
    // Acknowledged once planning on the active map avoids it.
    refresh_if_active(map_id, [done = std::move(done), id = *id]() mutable { done(id); });
  });
}

void MapCatalog::delete_zone(std::int64_t map_id, std::int64_t zone_id,
                             api::Completion<api::Done> done) {
  boost::asio::post(worker_, [this, map_id, zone_id, done = std::move(done)]() mutable {
    std::lock_guard lock(mutex_);
    switch (zones_.remove(map_id, zone_id)) {
      case db::ZoneStore::RemoveResult::kNoMap:
        return done(unknown_map());
      case db::ZoneStore::RemoveResult::kNoZone:
        return done(
            api::DomainError{api::ErrorKind::kNotFound, "unknown_zone", "no zone with this id"});
      case db::ZoneStore::RemoveResult::kRemoved:
        break;
    }
    refresh_if_active(map_id, [done = std::move(done)]() mutable { done(api::Done{}); });
  });
}

}  // namespace mobot::server
