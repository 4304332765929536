// Independent jobs worked on several threads, their results handed over in order on the caller's
// thread (load-time work: smoothing the stretches of a program's runs of lines). Not rt: it starts
// threads.
//
//   work(0) work(1) work(2) …        on up to `threads` threads (the caller's among them)
//   give(0) give(1) give(2) …        on the caller's thread, in order, each once work(k) is done
//
// A job is started only within `ahead` (at least four a thread) of the next one to hand over, so
// finished results waiting for a slow one before them stay few. work(k) must touch only what job k
// owns; give(k) may touch anything the caller owns. Errors end it as one thread would: where work(k)
// throws, every job before k is still handed over and then the error of the first job that failed
// is rethrown (whatever thread met it first); where give(k) throws, that is rethrown. Either way
// the caller hears it once every thread has stopped. A thread that cannot be started leaves the
// work to those that were (at worst the caller alone).
#pragma once

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace softmc::core {

// threads 0: one a hardware thread; ahead 0: four a thread.
template <class Work, class Give>
void ordered_parallel(std::size_t count, std::size_t threads, std::size_t ahead, Work&& work, Give&& give) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = std::min(threads, count);
  if (threads <= 1) {
    for (std::size_t k = 0; k < count; ++k) {
      work(k);
      give(k);
    }
    return;
  }
  ahead = std::max(ahead, 4 * threads);  // within 2 of each other, threads wait on a slow job
  std::mutex m;
  std::condition_variable cv;
  std::size_t next_take = 0, next_give = 0;
  std::size_t failed = count;  // the first job whose work threw (count: none)
  std::exception_ptr failed_error, give_error;
  std::vector<char> finished(count, 0);
  // Nothing is taken past the first failure, nor after a hand-over failed.
  const auto end = [&] { return std::min(count, give_error ? next_take : failed); };
  // Works on the next job within reach; false when there is none to take now.
  const auto take = [&](std::unique_lock<std::mutex>& lock) {
    if (next_take >= end() || next_take >= next_give + ahead) return false;
    const std::size_t k = next_take++;
    lock.unlock();
    std::exception_ptr e;
    try {
      work(k);
    } catch (...) {
      e = std::current_exception();
    }
    lock.lock();
    finished[k] = 1;
    if (e && k < failed) failed = k, failed_error = e;
    cv.notify_all();
    return true;
  };
  std::vector<std::thread> pool;
  pool.reserve(threads - 1);
  for (std::size_t t = 1; t < threads; ++t) {
    try {
      pool.emplace_back([&] {
        std::unique_lock<std::mutex> lock(m);
        while (next_take < end())
          if (!take(lock)) cv.wait(lock);
      });
    } catch (...) {
      break;  // fewer threads, the same jobs
    }
  }
  {
    std::unique_lock<std::mutex> lock(m);
    // Every job before the first failure is handed over; jobs past it that were taken finish.
    while (next_give < end() && !give_error) {
      if (finished[next_give]) {
        const std::size_t k = next_give++;
        cv.notify_all();  // one more may be taken
        lock.unlock();
        try {
          give(k);
        } catch (...) {
          lock.lock();
          give_error = std::current_exception();
          break;
        }
        lock.lock();
      } else if (!take(lock)) {
        cv.wait(lock);
      }
    }
    cv.notify_all();
  }
  for (auto& t : pool) t.join();
  if (give_error) std::rethrow_exception(give_error);
  if (failed_error) std::rethrow_exception(failed_error);
}

}  // namespace softmc::core
