#include "twin/base/cancellation.h"

namespace twin {
namespace {
thread_local const std::atomic<bool>* t_flag = nullptr;
}  // namespace

CancellationScope::CancellationScope(const std::atomic<bool>* flag) : previous_(t_flag) { t_flag = flag; }

CancellationScope::~CancellationScope() { t_flag = previous_; }

bool cancellation_requested() { return t_flag != nullptr && t_flag->load(std::memory_order_relaxed); }

const std::atomic<bool>* current_cancellation_flag() { return t_flag; }

}  // namespace twin
