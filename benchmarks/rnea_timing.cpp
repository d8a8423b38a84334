// Single-call timing of Pinocchio's C++ rnea on the benchmark chain (used by codegen_speed.py).
//
// The chain is built here with the same numbers as symgen's built-in "chain:n=N": joint i
// revolute about z (even i) or y (odd i), joint i>0 placed at (L,0,0) in link i-1, L = 0.1,
// mass 1 + 0.1 i, centre of mass (L/2,0,0), inertia about the COM diag(.01,.02,.03)(1 + 0.1 i),
// gravity (0,0,-9.81) (Pinocchio's default).
// Usage: ./rnea N STATES COUNT REPEATS OUT  (same file formats and output as codegen_timing.c)
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/rnea.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

static pinocchio::Model build_chain(int n)
{
    const double L = 0.1;
    pinocchio::Model model;
    pinocchio::JointIndex parent = 0;
    for (int i = 0; i < n; ++i) {
        pinocchio::SE3 placement(Eigen::Matrix3d::Identity(), Eigen::Vector3d(i == 0 ? 0.0 : L, 0.0, 0.0));
        std::string name = "j" + std::to_string(i);
        pinocchio::JointIndex id = (i % 2 == 0)
            ? model.addJoint(parent, pinocchio::JointModelRZ(), placement, name)
            : model.addJoint(parent, pinocchio::JointModelRY(), placement, name);
        const double s = 1.0 + 0.1 * i;
        Eigen::Matrix3d inertia = (Eigen::Vector3d(0.01, 0.02, 0.03) * s).asDiagonal();
        model.appendBodyToJoint(id, pinocchio::Inertia(1.0 + 0.1 * i, Eigen::Vector3d(L / 2, 0.0, 0.0), inertia),
                                pinocchio::SE3::Identity());
        parent = id;
    }
    return model;
}

int main(int argc, char **argv)
{
    if (argc != 6) {
        std::fprintf(stderr, "usage: %s N STATES COUNT REPEATS OUT\n", argv[0]);
        return 2;
    }
    const int n = std::atoi(argv[1]), count = std::atoi(argv[3]), repeats = std::atoi(argv[4]);
    pinocchio::Model model = build_chain(n);
    pinocchio::Data data(model);
    std::vector<double> raw(3 * static_cast<size_t>(count) * n);
    FILE *f = std::fopen(argv[2], "rb");
    if (!f || std::fread(raw.data(), sizeof(double), raw.size(), f) != raw.size()) {
        std::fprintf(stderr, "cannot read %s\n", argv[2]);
        return 2;
    }
    std::fclose(f);
    std::vector<Eigen::VectorXd> q(count), v(count), a(count);
    for (int i = 0; i < count; ++i) {
        q[i] = Eigen::Map<Eigen::VectorXd>(raw.data() + static_cast<size_t>(i) * n, n);
        v[i] = Eigen::Map<Eigen::VectorXd>(raw.data() + static_cast<size_t>(count + i) * n, n);
        a[i] = Eigen::Map<Eigen::VectorXd>(raw.data() + static_cast<size_t>(2 * count + i) * n, n);
    }
    std::vector<double> tau(static_cast<size_t>(count) * n);
    auto pass = [&]() {
        double sink = 0.0;
        for (int i = 0; i < count; ++i) {
            pinocchio::rnea(model, data, q[i], v[i], a[i]);
            Eigen::Map<Eigen::VectorXd>(tau.data() + static_cast<size_t>(i) * n, n) = data.tau;
            sink += data.tau[0];
        }
        return sink;
    };
    using clock = std::chrono::steady_clock;
    auto elapsed_ns = [](clock::time_point t0) {
        return std::chrono::duration<double, std::nano>(clock::now() - t0).count();
    };
    volatile double sink = pass();  // warm-up
    int loops = 1;                  // calibrate: one repeat lasts at least 20 ms
    for (;;) {
        auto t0 = clock::now();
        for (int k = 0; k < loops; ++k) sink = sink + pass();
        if (elapsed_ns(t0) > 2e7 || loops > (1 << 20)) break;
        loops *= 2;
    }
    std::vector<double> times(repeats);
    for (int r = 0; r < repeats; ++r) {
        auto t0 = clock::now();
        for (int k = 0; k < loops; ++k) sink = sink + pass();
        times[r] = elapsed_ns(t0) / (static_cast<double>(loops) * count);
    }
    std::sort(times.begin(), times.end());
    std::printf("%.3f %.3f\n", times[repeats / 2], times[0]);
    f = std::fopen(argv[5], "wb");
    if (!f || std::fwrite(tau.data(), sizeof(double), tau.size(), f) != tau.size()) return 2;
    std::fclose(f);
    return 0;
}
