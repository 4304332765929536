// The cyclic executor: an ordered list of cycle functions (read → update → write) run once per period.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace softmc::runtime {

struct CycleClock {
  std::uint64_t cycle = 0;  // cycles completed before this one
  double t_s = 0;           // time at the start of this cycle = cycle × period (no accumulated drift)
  double dt_s = 0;          // the period
};

using CycleFn = std::function<void(const CycleClock&)>;

// Virtual clock: time advances by exactly one period per step, so a simulation is deterministic
// and runs as fast as the host allows. (A real-time thread will drive the same list of functions.)
class VirtualExecutor {
 public:
  explicit VirtualExecutor(double period_s);

  // Configuration time: appends a cycle function; they run in the order added.
  void add(std::string name, CycleFn fn);
  // rt-safe as far as the functions are: runs one cycle.
  void step();
  // Steps until `done` is true after a cycle or `max_cycles` have run; returns cycles run.
  std::uint64_t run_until(const std::function<bool()>& done, std::uint64_t max_cycles);

  const CycleClock& clock() const { return clock_; }
  double period_s() const { return period_s_; }
  const std::vector<std::string>& order() const { return names_; }

 private:
  double period_s_;
  CycleClock clock_;
  std::vector<std::string> names_;
  std::vector<CycleFn> fns_;
};

}  // namespace softmc::runtime
