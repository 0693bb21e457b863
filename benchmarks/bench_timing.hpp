// Timing shared by the C++ benchmarks: the median of 7 repeats of `calls` calls of f(i), in ns per call.
#pragma once
#include <algorithm>
#include <chrono>
#include <vector>

template <typename F> double time_ns(F f, int calls) {
  std::vector<double> runs;
  for (int r = 0; r < 7; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < calls; ++i) f(i);
    auto t1 = std::chrono::steady_clock::now();
    runs.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / calls);
  }
  std::sort(runs.begin(), runs.end());
  return runs[runs.size() / 2];
}
