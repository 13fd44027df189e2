#include "twin/solvers/background_factorizer.h"

#include <algorithm>
#include <chrono>
#include <exception>

namespace twin {

BackgroundFactorizer::~BackgroundFactorizer() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  work_ready_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void BackgroundFactorizer::reset(const HessianPattern::Matrix& upper) {
  std::unique_lock lock(mutex_);
  queue_.clear();
  work_done_.wait(lock, [&] { return busy_ticket_ < 0; });
  ++pattern_id_;
  pattern_ = std::make_unique<HessianPattern::Matrix>(upper);
  for (Result& r : done_) spares_.emplace_back(std::move(r.factor), r.pattern_id);
  done_.clear();
}

void BackgroundFactorizer::submit(const HessianPattern::Matrix& upper, long ticket) {
  {
    std::lock_guard lock(mutex_);
    if (!worker_.joinable()) worker_ = std::thread([this] { run(); });
    // Only the newest submission is ever wanted: older ones waiting or finished are dropped.
    queue_.clear();
    for (Result& r : done_) spares_.emplace_back(std::move(r.factor), r.pattern_id);
    done_.clear();
    queue_.emplace_back(ticket, std::vector<double>(upper.valuePtr(), upper.valuePtr() + upper.nonZeros()));
  }
  work_ready_.notify_one();
}

BackgroundFactorizer::Taken BackgroundFactorizer::take(std::unique_ptr<SparseCholesky>& factor, long ticket) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_lock lock(mutex_);
  auto queued = [&] {
    return busy_ticket_ == ticket ||
           std::any_of(queue_.begin(), queue_.end(), [&](const auto& job) { return job.first == ticket; });
  };
  work_done_.wait(lock, [&] { return !queued(); });
  Taken taken;
  taken.waited_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  while (!done_.empty() && done_.front().ticket <= ticket) {
    Result& r = done_.front();
    if (r.ticket == ticket) {
      taken.found = true;
      taken.ok = r.ok;
      if (r.ok) std::swap(factor, r.factor);
    }
    if (r.factor) spares_.emplace_back(std::move(r.factor), r.pattern_id);
    done_.pop_front();
  }
  return taken;
}

std::pair<std::unique_ptr<SparseCholesky>, long> BackgroundFactorizer::spare_factor() {
  if (spares_.empty()) return {std::make_unique<SparseCholesky>(), -1};
  auto spare = std::move(spares_.back());
  spares_.pop_back();
  return spare;
}

void BackgroundFactorizer::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    work_ready_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    auto [ticket, values] = std::move(queue_.front());
    queue_.pop_front();
    const long pattern_id = pattern_id_;
    auto [factor, analysed_for] = spare_factor();
    busy_ticket_ = ticket;
    lock.unlock();

    // reset() waits while a job is busy, so the pattern is this job's until then.
    bool ok = false;
    try {
      std::copy(values.begin(), values.end(), pattern_->valuePtr());
      if (analysed_for != pattern_id) factor->analyze(*pattern_);
      analysed_for = pattern_id;
      ok = factor->factorize(*pattern_);
    } catch (const std::exception&) {  // out of memory in CHOLMOD: the solver falls back
      ok = false;
    }

    lock.lock();
    busy_ticket_ = -1;
    if (!queue_.empty()) {  // a newer submission is waiting: this one will not be taken
      spares_.emplace_back(std::move(factor), analysed_for);
    } else {
      done_.push_back({ticket, ok, analysed_for, std::move(factor)});
    }
    work_done_.notify_all();
  }
}

}  // namespace twin
