#include "api/client_registry.h"

#include "api/prometheus_text.h"

#include <utility>

namespace mobot::api {

ClientRecord::ClientRecord(std::uint64_t id, std::string address, double since_unix_s)
    : id_(id), address_(std::move(address)), since_unix_s_(since_unix_s) {}

void ClientRecord::identify(const Caller& caller) {
  std::lock_guard lock(mutex_);
  caller_ = caller;
}

void ClientRecord::became_stream() {
  std::lock_guard lock(mutex_);
  stream_ = true;
}

void ClientRecord::set_topics(std::vector<std::string> topics) {
  std::lock_guard lock(mutex_);
  topics_ = std::move(topics);
}

void ClientRecord::set_rtt_ms(double rtt_ms) {
  std::lock_guard lock(mutex_);
  rtt_ms_ = rtt_ms;
}

ClientRecord::View ClientRecord::view() const {
  View out;
  out.id = id_;
  out.address = address_;
  out.since_unix_s = since_unix_s_;
  out.bytes_sent = bytes_sent_.load(std::memory_order_relaxed);
  out.dropped = dropped_.load(std::memory_order_relaxed);
  std::lock_guard lock(mutex_);
  out.stream = stream_;
  out.caller = caller_;
  out.rtt_ms = rtt_ms_;
  out.topics = topics_;
  return out;
}

ClientRegistry::Registration::Registration(ClientRegistry& registry,
                                           std::shared_ptr<ClientRecord> record)
    : registry_(&registry), record_(std::move(record)) {}

ClientRegistry::Registration::Registration(Registration&& other) noexcept
    : registry_(std::exchange(other.registry_, nullptr)), record_(std::move(other.record_)) {}

ClientRegistry::Registration& ClientRegistry::Registration::operator=(
    Registration&& other) noexcept {
  if (this != &other) {
    reset();
    registry_ = std::exchange(other.registry_, nullptr);
    record_ = std::move(other.record_);
  }
  return *this;
}

ClientRegistry::Registration::~Registration() { reset(); }

void ClientRegistry::Registration::reset() {
  if (registry_ != nullptr && record_) registry_->close(record_->id());
  registry_ = nullptr;
  record_.reset();
}

ClientRegistry::Registration ClientRegistry::open(std::string address, double since_unix_s) {
  std::lock_guard lock(mutex_);
  auto record = std::make_shared<ClientRecord>(++last_id_, std::move(address), since_unix_s);
  open_.emplace(record->id(), record);
  return Registration(*this, std::move(record));
}

std::shared_ptr<ClientRecord> ClientRegistry::find(std::uint64_t id) const {
  std::lock_guard lock(mutex_);
  const auto it = open_.find(id);
  return it == open_.end() ? nullptr : it->second;
}

std::string ClientRegistry::metrics_text() const {
  std::string rtt;
  std::string sent;
  std::string dropped;
  for (const ClientRecord::View& client : list()) {
    // Streams only: HTTP connections come and go with each request.
    if (!client.stream) continue;
    const std::string labels = label("client", std::to_string(client.id)) + "," +
                               label("label", client.caller ? client.caller->label : "") + "," +
                               label("address", client.address);
    if (client.rtt_ms)
      append_sample(rtt, "mobot_stream_client_rtt_seconds", *client.rtt_ms / 1e3, labels);
    append_sample(sent, "mobot_stream_client_bytes_sent_total",
                  static_cast<double>(client.bytes_sent), labels);
    append_sample(dropped, "mobot_stream_client_frames_dropped_total",
                  static_cast<double>(client.dropped), labels);
  }
  std::string out;
  append_family(out, "mobot_stream_client_rtt_seconds", "gauge",
                "A stream's round trip, from its last timed ping.");
  out += rtt;
  append_family(out, "mobot_stream_client_bytes_sent_total", "counter",
                "Bytes written to a stream.");
  out += sent;
  append_family(out, "mobot_stream_client_frames_dropped_total", "counter",
                "Frames dropped for a stream that read too slowly.");
  out += dropped;
  return out;
}

std::vector<ClientRecord::View> ClientRegistry::list() const {
  std::vector<std::shared_ptr<ClientRecord>> records;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, record] : open_) records.push_back(record);
  }
  std::vector<ClientRecord::View> views;
  views.reserve(records.size());
  for (const auto& record : records) views.push_back(record->view());
  return views;
}

std::size_t ClientRegistry::size() const {
  std::lock_guard lock(mutex_);
  return open_.size();
}

void ClientRegistry::close(std::uint64_t id) {
  std::lock_guard lock(mutex_);
  open_.erase(id);
}

}  // namespace mobot::api
