#pragma once
// A typed wrapper around one LCM instance, in the style of Drake's DrakeLcmInterface:
// publish<T>(channel, msg), subscribe<T>(channel, callback) with decoding to T, and
// handle_for(timeout) to dispatch received messages on the caller's thread.
//
// Real-time rule: publish() and handle_for() never throw. A message that fails to decode (wrong
// fingerprint, truncated, trailing bytes, array counts that cannot fit in it: lcm_wire_check.h)
// or fails its check (drivers::message_problem, see
// lcm_message_checks.h) is dropped and counted, never handed to the callback; an exception from a
// callback is caught and counted. Only construction (bad URL) and subscribe() throw.
//
// Threads: subscribe, unsubscribe and handle_for belong to one thread (the one that handles);
// publish, counters() and last_problem() may be used from any thread. A callback may
// unsubscribe (its own or another subscription: removal waits until handle_for returns, and
// nothing more is delivered to it meanwhile) but must not subscribe.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <lcm/lcm.h>

#include "drivers/lcm_message_checks.h"
#include "drivers/lcm_wire_check.h"

namespace drivers {

// Loopback multicast, never leaves the host (ttl=0); LCM's own default group and port.
inline constexpr const char* kLoopbackLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

// Microseconds since the Unix epoch (the utime of every message); simulation time when the
// process runs on the fake world's clock (common/process_clock.h).
std::int64_t utime_now();

struct BusCounters {
  std::uint64_t delivered = 0;        // decoded, checked and handed to a callback
  std::uint64_t decode_failures = 0;  // wrong fingerprint, truncated or trailing bytes
  std::uint64_t rejected = 0;         // decoded but failed message_problem()
  std::uint64_t callback_errors = 0;  // the callback threw
  std::uint64_t publish_failures = 0; // refused (failed its check) or LCM could not send
};

struct HandleResult {
  enum class Status { kHandled, kTimeout, kError };
  Status status = Status::kTimeout;
  int messages = 0;  // messages LCM dispatched in this call (delivered or dropped)
};

class LcmBus {
 public:
  using SubscriptionId = int;

  // url: an LCM provider URL, e.g. "memq://" (in-process, tests) or kLoopbackLcmUrl. Throws
  // std::runtime_error naming the URL when LCM cannot start on it.
  explicit LcmBus(std::string url);
  ~LcmBus();
  LcmBus(const LcmBus&) = delete;
  LcmBus& operator=(const LcmBus&) = delete;

  const std::string& url() const { return url_; }

  // Checks and encodes `msg` and publishes it. Returns false (and counts it) when the message
  // fails its check or LCM cannot send it; the reason is in last_problem().
  template <typename T>
  bool publish(const std::string& channel, const T& msg);

  // Publishes already-encoded bytes (e.g. a message replayed from an lcm-logger log). Returns
  // false (and counts it) when LCM cannot send.
  bool publish_raw(const std::string& channel, const void* data, std::size_t size);

  // Calls on_message for each valid T received on `channel` (an LCM regular expression matched
  // against the whole channel name). Throws std::runtime_error if LCM refuses the subscription.
  template <typename T>
  SubscriptionId subscribe(const std::string& channel, std::function<void(const T&)> on_message);
  // The same, also passing the channel the message arrived on (for regex subscriptions).
  template <typename T>
  SubscriptionId subscribe_with_channel(
      const std::string& channel,
      std::function<void(const std::string& channel, const T&)> on_message);
  void unsubscribe(SubscriptionId id);

  // Waits up to `timeout` for a message, then dispatches it and every message already waiting
  // (at most max_messages in all). Never throws.
  HandleResult handle_for(std::chrono::milliseconds timeout, int max_messages = 1000);

  // Totals over all subscriptions and publishes; one subscription's counts (handling thread).
  BusCounters counters() const;
  BusCounters counters(SubscriptionId id) const;
  // The last dropped message's or failed publish's reason, with its channel ("" if none).
  std::string last_problem() const;

 private:
  enum class Outcome { kDelivered, kDecodeFailed, kRejected, kCallbackFailed };
  // Decodes, checks and delivers one raw message; fills `problem` when it is not delivered.
  // Runs on the handling thread.
  using Dispatch =
      std::function<Outcome(const void* data, int size, const std::string& channel,
                            std::string& problem)>;
  struct Subscription {
    SubscriptionId id = 0;
    std::string channel;
    Dispatch dispatch;
    lcm_subscription_t* handle = nullptr;
    BusCounters counters;
    LcmBus* bus = nullptr;
    bool closed = false;  // unsubscribed during dispatch, removed when handle_for returns
  };

  SubscriptionId add_subscription(const std::string& channel, Dispatch dispatch);
  void record_publish_failure(const std::string& channel, const std::string& problem);
  void remove_closed_subscriptions();
  static void on_raw_message(const lcm_recv_buf_t* buffer, const char* channel, void* user);

  std::string url_;
  lcm_t* lcm_ = nullptr;
  std::vector<std::unique_ptr<Subscription>> subscriptions_;  // stable addresses for LCM
  bool dispatching_ = false;  // inside handle_for: unsubscribe only marks subscriptions closed
  SubscriptionId next_id_ = 1;
  mutable std::mutex mutex_;  // guards totals_ and last_problem_ (publish may be on any thread)
  BusCounters totals_;
  std::string last_problem_;
};

template <typename T>
bool LcmBus::publish(const std::string& channel, const T& msg) {
  // Checked first: LCM's encoder trusts the counts and would read past a short vector.
  std::string problem = message_problem(msg);
  if (!problem.empty()) {
    record_publish_failure(channel, problem);
    return false;
  }
  const int size = msg.getEncodedSize();
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  if (msg.encode(bytes.data(), 0, size) != size) {
    record_publish_failure(channel, "encoding failed");
    return false;
  }
  return publish_raw(channel, bytes.data(), bytes.size());
}

template <typename T>
LcmBus::SubscriptionId LcmBus::subscribe(const std::string& channel,
                                         std::function<void(const T&)> on_message) {
  return subscribe_with_channel<T>(
      channel, [f = std::move(on_message)](const std::string&, const T& msg) { f(msg); });
}

template <typename T>
LcmBus::SubscriptionId LcmBus::subscribe_with_channel(
    const std::string& channel,
    std::function<void(const std::string& channel, const T&)> on_message) {
  if (!has_wire_layout(T::getTypeName())) {
    throw std::logic_error(std::string("LcmBus: no wire layout for ") + T::getTypeName() +
                           " (add it in drivers/lcm_wire_check.cc)");
  }
  Dispatch dispatch = [f = std::move(on_message)](const void* data, int size,
                                                  const std::string& arrived_on,
                                                  std::string& problem) {
    T msg;
    problem = decode_checked(data, size, msg);
    if (!problem.empty()) return Outcome::kDecodeFailed;
    problem = message_problem(msg);
    if (!problem.empty()) return Outcome::kRejected;
    try {
      f(arrived_on, msg);
    } catch (const std::exception& e) {
      problem = std::string("callback threw: ") + e.what();
      return Outcome::kCallbackFailed;
    } catch (...) {
      problem = "callback threw a non-standard exception";
      return Outcome::kCallbackFailed;
    }
    return Outcome::kDelivered;
  };
  return add_subscription(channel, std::move(dispatch));
}

}  // namespace drivers
