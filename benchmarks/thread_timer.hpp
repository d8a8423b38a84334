// Per-call timing shared by the C++ harnesses (rnea_timing.cpp, constrained_timing.cpp), on the
// clock the generated code's C harness reads: the CPU time of this thread, so time slices given to
// other processes are not counted.
#pragma once

#include <algorithm>
#include <ctime>
#include <utility>
#include <vector>

inline double thread_cpu_ns()
{
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return 1e9 * static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec);
}

// Median and minimum nanoseconds per call over `repeats` timed runs of `pass` (one call per state
// over `count` states, returning a checksum so that nothing is optimised away). One warm-up pass;
// each timed run repeats the pass often enough to last at least 20 ms.
template <class Pass>
std::pair<double, double> time_per_call(Pass &&pass, int count, int repeats)
{
    volatile double sink = pass();
    int loops = 1;
    for (;;) {
        const double t0 = thread_cpu_ns();
        for (int k = 0; k < loops; ++k) sink = sink + pass();
        if (thread_cpu_ns() - t0 > 2e7 || loops > (1 << 20)) break;
        loops *= 2;
    }
    std::vector<double> times(repeats);
    for (int r = 0; r < repeats; ++r) {
        const double t0 = thread_cpu_ns();
        for (int k = 0; k < loops; ++k) sink = sink + pass();
        times[r] = (thread_cpu_ns() - t0) / (static_cast<double>(loops) * count);
    }
    std::sort(times.begin(), times.end());
    return {times[repeats / 2], times[0]};
}
