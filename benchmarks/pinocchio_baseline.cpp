// Pinocchio's C++ rnea / aba / crba timed the way Pinocchio's own benchmark program does it
// (written here from a reading of its benchmark/timings.cpp; no code taken from it), used by
// pinocchio_baseline.py beside our harness rnea_timing.cpp.
//
// Model: parsed from the URDF by Pinocchio's own parser (fixed base, as with the program's "--no-ff")
// in pinocchio_baseline.py, which saves it with Model::saveToText; read here with loadFromText (the
// wheel ships no urdfdom headers, so the C++ parser cannot be compiled against it; a text archive
// also carries no Eigen alignment ABI across builds with and without -march=native).
// Methods (argv[2]):
// * random: Pinocchio 2 / 3's timings.cpp: STATES states drawn with randomConfiguration in [-1, 1]
//   and Eigen's Random, one pass over them between two wall-clock readings (gettimeofday), time
//   divided by STATES (the program's default is 100 000 states).
// * fixed: the Google-Benchmark version of timings.cpp (Pinocchio 3.5 on): one random state, the
//   algorithm called through a non-inlined function in a loop long enough to last >= 0.5 s.
// Each round prints "wall_ns cpu_ns" per call: the wall clock the program reads, and the CPU time
// of this thread over the same loop (the clock of our harness).
// Usage: ./pinocchio_baseline MODEL_TXT random|fixed rnea|aba|crba STATES ROUNDS
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/serialization.hpp>

#include "thread_timer.hpp"

#include <sys/time.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

static double wall_s()
{
    timeval t;
    gettimeofday(&t, nullptr);
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
}

static double cpu_s() { return 1e-9 * thread_cpu_ns(); }

enum class Algo { rnea, aba, crba };

__attribute__((noinline)) static void call(Algo algo, const pinocchio::Model &model, pinocchio::Data &data,
                                           const Eigen::VectorXd &q, const Eigen::VectorXd &v,
                                           const Eigen::VectorXd &a)
{
    switch (algo) {
    case Algo::rnea: pinocchio::rnea(model, data, q, v, a); break;
    case Algo::aba: pinocchio::aba(model, data, q, v, a); break;  // a plays tau
    case Algo::crba: pinocchio::crba(model, data, q); break;
    }
}

int main(int argc, char **argv)
{
    if (argc != 6) {
        std::fprintf(stderr, "usage: %s MODEL_TXT random|fixed rnea|aba|crba STATES ROUNDS\n", argv[0]);
        return 2;
    }
    const std::string method = argv[2], name = argv[3];
    const Algo algo = name == "aba" ? Algo::aba : name == "crba" ? Algo::crba : Algo::rnea;
    const int count = std::atoi(argv[4]), rounds = std::atoi(argv[5]);
    pinocchio::Model model;
    model.loadFromText(argv[1]);
    pinocchio::Data data(model);
    std::srand(7);
    const Eigen::VectorXd qmax = Eigen::VectorXd::Ones(model.nq);
    const int states = method == "fixed" ? 1 : count;
    std::vector<Eigen::VectorXd> q(states), v(states), a(states);
    for (int i = 0; i < states; ++i) {
        q[i] = pinocchio::randomConfiguration(model, -qmax, qmax);
        v[i] = Eigen::VectorXd::Random(model.nv);
        a[i] = Eigen::VectorXd::Random(model.nv);
    }
    std::printf("nv %d\n", model.nv);
    long loops = count;
    if (method == "fixed") {  // as many calls as last 0.5 s, found once
        for (const double t0 = wall_s(); wall_s() - t0 < 0.1;) call(algo, model, data, q[0], v[0], a[0]);
        for (loops = 1000;; loops *= 2) {
            const double t0 = wall_s();
            for (long k = 0; k < loops; ++k) call(algo, model, data, q[0], v[0], a[0]);
            if (wall_s() - t0 > 0.5) break;
        }
    }
    for (int r = 0; r < rounds; ++r) {
        const double w0 = wall_s(), c0 = cpu_s();
        if (method == "fixed")
            for (long k = 0; k < loops; ++k) call(algo, model, data, q[0], v[0], a[0]);
        else
            for (int i = 0; i < count; ++i) call(algo, model, data, q[i], v[i], a[i]);
        const double c1 = cpu_s(), w1 = wall_s();
        std::printf("%.3f %.3f\n", 1e9 * (w1 - w0) / loops, 1e9 * (c1 - c0) / loops);
    }
    // a checksum of the last result, so that no call can be dropped
    const double check = algo == Algo::rnea ? data.tau[0] : algo == Algo::aba ? data.ddq[0] : data.M(0, 0);
    std::printf("check %.17g\n", check);
    return 0;
}
