// Timing for the C++ benchmark programs (benchmarks/pinocchio_platform_bench.cpp): thread CPU
// time (CLOCK_THREAD_CPUTIME_ID) and the passes of benchmarks/harness_main.c.
#pragma once
#include <cstdio>
#include <functional>
#include <string>
#include <time.h>
#include <vector>

inline double bench_cpu_ns() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e9 + t.tv_nsec;
}

// The harness's method (benchmarks/harness_main.c) for a C++ timing program: each case is a
// function (e.g. "inverse_dynamics") and a side (e.g. "symdyn", "pinocchio_lcaba") with a call
// f(state); one pass calls it once per state and its thread CPU time per call is recorded.
// After one untimed warm-up pass of every case, the sides of one function take turns, pass
// after pass (their order rotated each pass).  Prints "time FUNCTION SIDE ns ns ..." (one number
// per pass), the format benchmarks/harness.py reads.

struct TimedCase {
  std::string function, side;
  std::function<double()> pass;  // one pass over every state: ns per call
};

// A case whose pass calls f(s) for s = 0 .. states - 1 (f inlined into the loop), adding its
// results into sink so that no call can be dropped.
template <typename F> TimedCase timed_case(const char *function, const char *side, F f, int states, double &sink) {
  return {function, side, [f, states, &sink]() {
            double acc = 0.0;
            const double t0 = bench_cpu_ns();
            for (int s = 0; s < states; ++s) acc += f(s);
            const double t1 = bench_cpu_ns();
            sink += acc;
            return (t1 - t0) / states;
          }};
}

// Cases of one function must be adjacent in `cases`.
inline void interleaved_passes(std::vector<TimedCase> &cases, int passes) {
  const int n = (int)cases.size();
  for (auto &c : cases) c.pass();  // warm-up
  std::vector<double> times((size_t)passes * n);
  for (int r = 0; r < passes; ++r)
    for (int g = 0, end; g < n; g = end) {
      for (end = g; end < n && cases[end].function == cases[g].function; ++end) {}
      for (int j = 0; j < end - g; ++j) {
        const int i = g + (j + r) % (end - g);
        times[(size_t)r * n + i] = cases[i].pass();
      }
    }
  for (int i = 0; i < n; ++i) {
    std::printf("time %s %s", cases[i].function.c_str(), cases[i].side.c_str());
    for (int r = 0; r < passes; ++r) std::printf(" %.2f", times[(size_t)r * n + i]);
    std::printf("\n");
  }
}
