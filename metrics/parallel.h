// The one way metrics spread work over the cores: parallel_for(n, fn) calls
// fn(i) for every i in [0, n) from up to hardware_concurrency threads (the
// caller's included) and returns when all are done. Work items are taken in
// chunks in order; callers that sum write per-item partials and add them up
// in order afterwards, so results do not depend on the thread count.
// (Plain std::thread rather than OpenMP: no busy-waiting workers that would
// take the cores from lavapipe's rasteriser threads between metric calls.)
// GLINTLAB_METRIC_THREADS=n caps the threads (1: serial; the benchmark uses it
// to show what the threads buy).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <thread>
#include <vector>

namespace glintlab::metrics {

inline long metric_threads() {
  static const long n = [] {
    const char* env = std::getenv("GLINTLAB_METRIC_THREADS");
    const long cap = env ? std::atol(env) : 0;
    const long hw = std::max(1L, long(std::thread::hardware_concurrency()));
    return cap > 0 ? std::min(cap, hw) : hw;
  }();
  return n;
}

template <typename Fn>
void parallel_for(long n, Fn&& fn, long chunk = 0) {
  if (n <= 0) return;
  const long threads = std::max(1L, std::min<long>(n, metric_threads()));
  if (chunk <= 0) chunk = std::max(1L, n / (threads * 8));
  std::atomic<long> next{0};
  auto work = [&] {
    for (long begin = next.fetch_add(chunk); begin < n; begin = next.fetch_add(chunk))
      for (long i = begin, end = std::min(n, begin + chunk); i < end; ++i) fn(i);
  };
  std::vector<std::thread> pool;
  for (long t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& th : pool) th.join();
}

}  // namespace glintlab::metrics
