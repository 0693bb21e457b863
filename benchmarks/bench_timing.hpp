// Timing shared by the C++ benchmarks: the median of 7 repeats of `calls` calls of f(i), in ns per
// call of thread CPU time (CLOCK_THREAD_CPUTIME_ID, as benchmarks/harness_main.c).
#pragma once
#include <algorithm>
#include <time.h>
#include <vector>

inline double bench_cpu_ns() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e9 + t.tv_nsec;
}

template <typename F> double time_ns(F f, int calls) {
  std::vector<double> runs;
  for (int r = 0; r < 7; ++r) {
    const double t0 = bench_cpu_ns();
    for (int i = 0; i < calls; ++i) f(i);
    runs.push_back((bench_cpu_ns() - t0) / calls);
  }
  std::sort(runs.begin(), runs.end());
  return runs[runs.size() / 2];
}
