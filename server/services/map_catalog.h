#pragma once

#include <atomic>
#include <mutex>
#include <vector>

#include <boost/asio/thread_pool.hpp>

#include "api/ports/map_catalog_port.h"
#include "db/map_store.h"
#include "db/zone_store.h"
#include "server/map_listener.h"
#include "server/runtime.h"

namespace mobot::server {

// The MapCatalogPort and the activation of maps: the heavy preparation of every map listener runs
// on a worker of its own, one map at a time; the listeners then switch over on the control loop,
// between two ticks, and the `map` topic sends the new map.
class MapCatalog final : public api::MapCatalogPort {
 public:
  MapCatalog(db::MapStore& maps, db::ZoneStore& zones, Runtime& runtime,
             std::vector<MapListener*> listeners);
  ~MapCatalog() override;

  std::vector<api::MapInfo> list_maps() const override;
  std::optional<api::MapInfo> map_info(std::int64_t id) const override;
  std::optional<mapping::OccupancyGrid> map_grid(std::int64_t id) const override;
  std::int64_t import_map(const std::string& name, const mapping::OccupancyGrid& grid) override;
  void activate_map(std::int64_t id, api::Completion<api::MapInfo> done) override;
  void delete_map(std::int64_t id) override;
  std::optional<std::vector<mapping::KeepoutZone>> list_zones(std::int64_t map_id) const override;
  void add_zone(std::int64_t map_id, const std::string& name,
                const std::vector<geometry::Point2D>& polygon,
                api::Completion<std::int64_t> done) override;
  void delete_zone(std::int64_t map_id, std::int64_t zone_id,
                   api::Completion<api::Done> done) override;

  // Whether ensure_named_map takes the active map from another: a world chosen now does, the world
  // found at start-up does not (the map the user activated, or saved from mapping, stays active
  // across restarts).
  enum class Activation { kAlways, kWhenNoneActive };
  // Makes the map called `name` active, storing `floor` under that name first when no map has it
  // (a simulated world's surveyed map). Thread-safe.
  void ensure_named_map(const std::string& name, const mapping::OccupancyGrid& floor,
                        Activation activation);
  // Prepares the active map on the caller's thread and posts the switch: at start-up, before the
  // control loop runs, so the first tick already has it.
  void activate_stored_now();
  // Activates the stored active map again (after a world change), completing once it is in use.
  void reactivate(api::Completion<api::Done> done);
  // Waits for an activation under way (its reply is dropped if the server stops first).
  void stop() { worker_.join(); }

 private:
  // Prepares map `id` on the caller's thread and posts the switch; `done` runs on the loop.
  void switch_to(std::int64_t id, std::function<void()> done);
  // After a change of map `map_id`'s zones: when it is the active map, its listeners get them
  // before `done` runs; otherwise `done` runs at once. Called on the worker with the lock held.
  void refresh_if_active(std::int64_t map_id, std::function<void()> done);

  db::MapStore& maps_;
  db::ZoneStore& zones_;
  Runtime& runtime_;
  const std::vector<MapListener*> listeners_;
  std::mutex mutex_;  // serialises activation, deletion and the naming of world maps
  std::uint64_t generation_ = 0;
  boost::asio::thread_pool worker_{1};
};

}  // namespace mobot::server
