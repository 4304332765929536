// Virtual-clock cycle execution.
#include "runtime/executor.hpp"

#include <stdexcept>

namespace softmc::runtime {

VirtualExecutor::VirtualExecutor(double period_s) : period_s_(period_s) {
  if (!(period_s > 0)) throw std::invalid_argument("cycle period must be > 0");
  clock_.dt_s = period_s;
}

void VirtualExecutor::add(std::string name, CycleFn fn) {
  names_.push_back(std::move(name));
  fns_.push_back(std::move(fn));
}

void VirtualExecutor::step() {
  clock_.t_s = static_cast<double>(clock_.cycle) * period_s_;
  for (auto& f : fns_) f(clock_);
  ++clock_.cycle;
}

std::uint64_t VirtualExecutor::run_until(const std::function<bool()>& done, std::uint64_t max_cycles) {
  std::uint64_t n = 0;
  while (n < max_cycles) {
    step();
    ++n;
    if (done()) break;
  }
  return n;
}

}  // namespace softmc::runtime
