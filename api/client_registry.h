#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "api/ports/token_admin_port.h"

namespace mobot::api {

// One open connection, as GET /api/v1/clients shows it. The connection updates it as it learns who
// its client is and what it sends; the registry only reads it.
class ClientRecord {
 public:
  ClientRecord(std::uint64_t id, std::string address, double since_unix_s);

  struct View {
    std::uint64_t id = 0;
    bool stream = false;
    std::optional<Caller> caller;  // unknown until a request authenticates
    std::string address;
    double since_unix_s = 0.0;
    std::optional<double> rtt_ms;
    std::vector<std::string> topics;
    std::uint64_t bytes_sent = 0;
    std::uint64_t dropped = 0;
  };

  std::uint64_t id() const { return id_; }
  void identify(const Caller& caller);
  // The HTTP connection became a WebSocket stream.
  void became_stream();
  void set_topics(std::vector<std::string> topics);
  void set_rtt_ms(double rtt_ms);
  void add_sent(std::uint64_t bytes) { bytes_sent_.fetch_add(bytes, std::memory_order_relaxed); }
  void add_dropped() { dropped_.fetch_add(1, std::memory_order_relaxed); }
  View view() const;

 private:
  const std::uint64_t id_;
  const std::string address_;
  const double since_unix_s_;
  std::atomic<std::uint64_t> bytes_sent_{0};
  std::atomic<std::uint64_t> dropped_{0};
  mutable std::mutex mutex_;  // guards the fields below
  bool stream_ = false;
  std::optional<Caller> caller_;
  std::optional<double> rtt_ms_;
  std::vector<std::string> topics_;
};

// Every open connection of the server, HTTP and stream alike. A connection holds its registration
// for as long as it lives; dropping it takes the connection off the list. Thread-safe.
class ClientRegistry {
 public:
  class Registration {
   public:
    Registration() = default;
    Registration(ClientRegistry& registry, std::shared_ptr<ClientRecord> record);
    Registration(Registration&& other) noexcept;
    Registration& operator=(Registration&& other) noexcept;
    Registration(const Registration&) = delete;
    Registration& operator=(const Registration&) = delete;
    ~Registration();

    ClientRecord* operator->() const { return record_.get(); }
    const std::shared_ptr<ClientRecord>& record() const { return record_; }

   private:
    void reset();

    ClientRegistry* registry_ = nullptr;
    std::shared_ptr<ClientRecord> record_;
  };

  // A new connection from `address` ("ip:port"), with an id unique in this process.
  Registration open(std::string address, double since_unix_s);
  // The record of a connection, if it is still open.
  std::shared_ptr<ClientRecord> find(std::uint64_t id) const;
  std::vector<ClientRecord::View> list() const;
  // Per open stream: its round trip, bytes sent and frames dropped (Prometheus text).
  std::string metrics_text() const;
  std::size_t size() const;

 private:
  void close(std::uint64_t id);

  mutable std::mutex mutex_;
  std::map<std::uint64_t, std::shared_ptr<ClientRecord>> open_;
  std::uint64_t last_id_ = 0;
};

}  // namespace mobot::api
