#include "drivers/lcm_bus.h"

#include "common/process_clock.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace drivers {

std::int64_t utime_now() { return prepreg::process_epoch_us(); }

LcmBus::LcmBus(std::string url) : url_(std::move(url)) {
  lcm_ = lcm_create(url_.c_str());
  if (lcm_ == nullptr) {
    std::string message = "cannot start LCM on '" + url_ + "'";
    if (url_.rfind("udpm://", 0) == 0) {
      message +=
          " (UDP multicast: is there a multicast route? On loopback: "
          "ip route add 224.0.0.0/4 dev lo)";
    } else {
      message += " (expected e.g. memq:// or " + std::string(kLoopbackLcmUrl) + ")";
    }
    throw std::runtime_error(message);
  }
}

LcmBus::~LcmBus() {
  for (auto& s : subscriptions_) lcm_unsubscribe(lcm_, s->handle);
  lcm_destroy(lcm_);
}

bool LcmBus::publish_raw(const std::string& channel, const void* data, std::size_t size) {
  if (lcm_publish(lcm_, channel.c_str(), data, static_cast<unsigned>(size)) != 0) {
    record_publish_failure(channel, "LCM could not send");
    return false;
  }
  return true;
}

void LcmBus::record_publish_failure(const std::string& channel, const std::string& problem) {
  std::lock_guard lock(mutex_);
  ++totals_.publish_failures;
  last_problem_ = "publish " + channel + ": " + problem;
}

LcmBus::SubscriptionId LcmBus::add_subscription(const std::string& channel, Dispatch dispatch) {
  auto subscription = std::make_unique<Subscription>();
  subscription->id = next_id_++;
  subscription->channel = channel;
  subscription->dispatch = std::move(dispatch);
  subscription->bus = this;
  subscription->handle =
      lcm_subscribe(lcm_, channel.c_str(), &LcmBus::on_raw_message, subscription.get());
  if (subscription->handle == nullptr) {
    throw std::runtime_error("LCM on '" + url_ + "' refused a subscription to '" + channel + "'");
  }
  subscriptions_.push_back(std::move(subscription));
  return subscriptions_.back()->id;
}

void LcmBus::unsubscribe(SubscriptionId id) {
  auto it = std::find_if(subscriptions_.begin(), subscriptions_.end(),
                         [id](const auto& s) { return s->id == id; });
  if (it == subscriptions_.end()) return;
  (*it)->closed = true;
  // From a callback the subscription (and LCM's handler list) is in use: remove it afterwards.
  if (!dispatching_) remove_closed_subscriptions();
}

void LcmBus::remove_closed_subscriptions() {
  for (auto it = subscriptions_.begin(); it != subscriptions_.end();) {
    if ((*it)->closed) {
      lcm_unsubscribe(lcm_, (*it)->handle);
      it = subscriptions_.erase(it);
    } else {
      ++it;
    }
  }
}

void LcmBus::on_raw_message(const lcm_recv_buf_t* buffer, const char* channel, void* user) {
  auto* s = static_cast<Subscription*>(user);
  if (s->closed) return;
  LcmBus& bus = *s->bus;
  std::string problem;
  const std::string arrived_on(channel);
  Outcome outcome = Outcome::kDecodeFailed;
  try {
    outcome = s->dispatch(buffer->data, static_cast<int>(buffer->data_size), arrived_on, problem);
  } catch (...) {
    // Decoding allocates; running out of memory must not unwind through LCM's C code.
    problem = "out of memory while decoding";
  }
  std::uint64_t BusCounters::*counter = &BusCounters::delivered;
  switch (outcome) {
    case Outcome::kDelivered: counter = &BusCounters::delivered; break;
    case Outcome::kDecodeFailed: counter = &BusCounters::decode_failures; break;
    case Outcome::kRejected: counter = &BusCounters::rejected; break;
    case Outcome::kCallbackFailed: counter = &BusCounters::callback_errors; break;
  }
  std::lock_guard lock(bus.mutex_);
  ++(s->counters.*counter);
  ++(bus.totals_.*counter);
  if (outcome != Outcome::kDelivered) bus.last_problem_ = arrived_on + ": " + problem;
}

HandleResult LcmBus::handle_for(std::chrono::milliseconds timeout, int max_messages) {
  HandleResult result;
  const int wait_ms = static_cast<int>(std::clamp<std::int64_t>(
      timeout.count(), 0, std::numeric_limits<int>::max()));
  dispatching_ = true;
  const int first = lcm_handle_timeout(lcm_, wait_ms);
  if (first < 0) {
    result.status = HandleResult::Status::kError;
  } else if (first > 0) {
    result.status = HandleResult::Status::kHandled;
    result.messages = 1;
    while (result.messages < max_messages) {
      const int next = lcm_handle_timeout(lcm_, 0);
      if (next < 0) result.status = HandleResult::Status::kError;
      if (next <= 0) break;
      ++result.messages;
    }
  }
  dispatching_ = false;
  remove_closed_subscriptions();
  return result;
}

BusCounters LcmBus::counters() const {
  std::lock_guard lock(mutex_);
  return totals_;
}

std::string LcmBus::last_problem() const {
  std::lock_guard lock(mutex_);
  return last_problem_;
}

BusCounters LcmBus::counters(SubscriptionId id) const {
  for (const auto& s : subscriptions_) {
    if (s->id == id) return s->counters;
  }
  return {};
}

}  // namespace drivers
