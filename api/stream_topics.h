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

struct TopicSpec {
  TopicId id;
  std::string_view name;
  std::uint16_t binary_id;  // 0: JSON only
  bool sim_only;
  // A stream of samples where only the newest matters, which max_rate_hz may thin. The others
  // (map, events, goals, paths, cloud chunks) lose information when a message is skipped.
  bool sampled;
};

inline constexpr std::array<TopicSpec, kTopicCount> kTopics{{
    {TopicId::kPose, "pose", 0, false, true},
    {TopicId::kOdom, "odom", 0, false, true},
    {TopicId::kScan, "scan", 1, false, true},
    {TopicId::kSonar, "sonar", 0, false, true},
    {TopicId::kMap, "map", 2, false, false},
    {TopicId::kStatus, "status", 0, false, true},
    {TopicId::kEvents, "events", 0, false, false},
    {TopicId::kTruth, "truth", 0, true, true},
    {TopicId::kPath, "path", 0, false, false},
    {TopicId::kGoal, "goal", 0, false, false},
    {TopicId::kCloud, "cloud", 3, false, false},
    {TopicId::kIr, "ir", 0, false, true},
    {TopicId::kCostmap, "costmap", 4, false, true},
    {TopicId::kLocalCostmap, "local_costmap", 4, false, true},
    {TopicId::kParticles, "particles", 6, false, true},
    // One JPEG per frame (binary body: the file), at the camera driver's rate.
    {TopicId::kCamera, "camera", 5, false, true},
    // The tracked target, as GET /api/v1/tracking, on every frame the tracker processed.
    {TopicId::kTarget, "target", 0, false, true},
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
