#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace mobot::api {

// Every topic the stream offers. Bulk topics also have a binary encoding (README: binary frames).
enum class TopicId : std::uint8_t {
  kPose,
  kOdom,
  kScan,
  kSonar,
  kMap,
  kStatus,
  kEvents,
  kTruth,
  kPath,
  kGoal,
  kCloud,
  kIr,
  kCostmap,
  kLocalCostmap,
  kParticles,
  kCamera,
  kTarget
};
inline constexpr std::size_t kTopicCount = 17;

// What goes first to a client on a thin link, and what thins out first under its max_kbps: the
// robot's state and commands' outcomes, then what its sensors see, then the bulk.
enum class TopicPriority : std::uint8_t { kState = 0, kSensor = 1, kBulk = 2 };
inline constexpr std::size_t kPriorityCount = 3;

struct TopicSpec {
  TopicId id;
  std::string_view name;
  std::uint16_t binary_id;  // 0: JSON only
  bool sim_only;
  // A stream of samples where only the newest matters, which max_rate_hz may thin. The others
  // (map, events, goals, paths, cloud chunks) lose information when a message is skipped.
  bool sampled;
  TopicPriority priority;
};

inline constexpr std::array<TopicSpec, kTopicCount> kTopics{{
    {TopicId::kPose, "pose", 0, false, true, TopicPriority::kState},
    {TopicId::kOdom, "odom", 0, false, true, TopicPriority::kState},
    {TopicId::kScan, "scan", 1, false, true, TopicPriority::kSensor},
    {TopicId::kSonar, "sonar", 0, false, true, TopicPriority::kSensor},
    {TopicId::kMap, "map", 2, false, false, TopicPriority::kBulk},
    {TopicId::kStatus, "status", 0, false, true, TopicPriority::kState},
    {TopicId::kEvents, "events", 0, false, false, TopicPriority::kState},
    {TopicId::kTruth, "truth", 0, true, true, TopicPriority::kState},
    {TopicId::kPath, "path", 0, false, false, TopicPriority::kState},
    {TopicId::kGoal, "goal", 0, false, false, TopicPriority::kState},
    {TopicId::kCloud, "cloud", 3, false, false, TopicPriority::kBulk},
    {TopicId::kIr, "ir", 0, false, true, TopicPriority::kSensor},
    {TopicId::kCostmap, "costmap", 4, false, true, TopicPriority::kSensor},
    {TopicId::kLocalCostmap, "local_costmap", 4, false, true, TopicPriority::kSensor},
    {TopicId::kParticles, "particles", 6, false, true, TopicPriority::kSensor},
    // One JPEG per frame (binary body: the file), at the camera driver's rate.
    {TopicId::kCamera, "camera", 5, false, true, TopicPriority::kBulk},
    // The tracked target, as GET /api/v1/tracking, on every frame the tracker processed.
    {TopicId::kTarget, "target", 0, false, true, TopicPriority::kState},
}};

// The map body's flags (README: binary frames): bit 0, the frame holds changed tiles.
inline constexpr std::uint32_t kMapFlagTiles = 1;

inline constexpr const TopicSpec& topic_spec(TopicId id) {
  return kTopics[static_cast<std::size_t>(id)];
}

inline constexpr std::size_t topic_index(TopicId id) { return static_cast<std::size_t>(id); }

inline std::optional<TopicId> topic_from_name(std::string_view name) {
  for (const auto& spec : kTopics) {
    if (spec.name == name) return spec.id;
  }
  return std::nullopt;
}

}  // namespace mobot::api
