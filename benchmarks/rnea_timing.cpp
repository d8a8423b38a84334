// Single-call timing of Pinocchio's C++ rnea (used by codegen_speed.py), or of its aba when built
// with -DTIME_ABA (used by forward_speed.py: the third input is then tau, the output ddq).
//
// MODEL is either a number N or a model file.
// * N: the benchmark chain, built here with the same numbers as symgen's built-in "chain:n=N":
//   joint i revolute about z (even i) or y (odd i), joint i>0 placed at (L,0,0) in link i-1,
//   L = 0.1, mass 1 + 0.1 i, centre of mass (L/2,0,0), inertia about the COM
//   diag(.01,.02,.03)(1 + 0.1 i), gravity (0,0,-9.81) (Pinocchio's default).
// * a file: a robot that Pinocchio's Python URDF parser built from a URDF file (UR5, Panda),
//   written by codegen_speed.py as text: the number of joints, then per joint "parent type ax ay az
//   R(9, row-major) p(3) mass c(3) Ixx Ixy Iyy Ixz Iyz Izz", type a code of pinocchio_joints.hpp
//   (RX ... PU, S, or FF: a free flyer for floating-base robots). The model is rebuilt here with addJoint and
//   appendBodyToJoint, so every Pinocchio template is compiled with this file's flags and no
//   object crosses to the precompiled library (whose Eigen alignment ABI differs under
//   -march=native).
// Usage: ./rnea MODEL STATES COUNT REPEATS OUT  (same file formats and output as codegen_timing.c;
// STATES holds COUNT q's of model.nq entries each, then the v's and a's of model.nv)
// Built with -DTIME_DERIVATIVES (used by derivative_speed.py) it takes a sixth argument, rnea or
// aba, and times computeRNEADerivatives (q, v, a) or computeABADerivatives (q, v, tau); OUT then
// holds per state the three nv x nv matrices row-major: dtau_dq, dtau_dv, M (or ddq_dq, ddq_dv,
// Minv), the symmetric ones completed from the upper triangle Pinocchio fills.
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#if defined(TIME_ABA) || defined(TIME_DERIVATIVES)
#include <pinocchio/algorithm/aba.hpp>
#endif
#ifdef TIME_DERIVATIVES
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/aba-derivatives.hpp>
#endif

#include "pinocchio_joints.hpp"
#include "thread_timer.hpp"

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <fstream>
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

static pinocchio::Model read_model(const char *path)
{
    std::ifstream in(path);
    int joints = 0;
    if (!(in >> joints)) {
        std::fprintf(stderr, "cannot read %s\n", path);
        std::exit(2);
    }
    pinocchio::Model model;
    for (int i = 1; i <= joints; ++i) {
        int parent;
        std::string type;
        Eigen::Vector3d axis, p, c;
        Eigen::Matrix3d r;
        double mass, ixx, ixy, iyy, ixz, iyz, izz;
        in >> parent >> type >> axis[0] >> axis[1] >> axis[2];
        for (int k = 0; k < 9; ++k) in >> r(k / 3, k % 3);
        in >> p[0] >> p[1] >> p[2] >> mass >> c[0] >> c[1] >> c[2] >> ixx >> ixy >> iyy >> ixz >> iyz >> izz;
        if (!in) {
            std::fprintf(stderr, "bad joint %d in %s\n", i, path);
            std::exit(2);
        }
        Eigen::Matrix3d inertia;
        inertia << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
        pinocchio::JointIndex id = add_joint(model, static_cast<pinocchio::JointIndex>(parent), type, axis,
                                             pinocchio::SE3(r, p), "j" + std::to_string(i));
        model.appendBodyToJoint(id, pinocchio::Inertia(mass, c, inertia), pinocchio::SE3::Identity());
    }
    return model;
}

int main(int argc, char **argv)
{
#ifdef TIME_DERIVATIVES
    if (argc != 7) {
        std::fprintf(stderr, "usage: %s N|MODEL_FILE STATES COUNT REPEATS OUT rnea|aba\n", argv[0]);
        return 2;
    }
    const bool aba_derivatives = std::string(argv[6]) == "aba";
#else
    if (argc != 6) {
        std::fprintf(stderr, "usage: %s N|MODEL_FILE STATES COUNT REPEATS OUT\n", argv[0]);
        return 2;
    }
#endif
    const bool is_file = std::string(argv[1]).find_first_not_of("0123456789") != std::string::npos;
    pinocchio::Model model = is_file ? read_model(argv[1]) : build_chain(std::atoi(argv[1]));
    const int n = model.nv, nq = model.nq, count = std::atoi(argv[3]), repeats = std::atoi(argv[4]);
    pinocchio::Data data(model);
    std::vector<double> raw(static_cast<size_t>(count) * (nq + 2 * n));
    FILE *f = std::fopen(argv[2], "rb");
    if (!f || std::fread(raw.data(), sizeof(double), raw.size(), f) != raw.size()) {
        std::fprintf(stderr, "cannot read %s\n", argv[2]);
        return 2;
    }
    std::fclose(f);
    std::vector<Eigen::VectorXd> q(count), v(count), a(count);
    for (int i = 0; i < count; ++i) {
        double *vs = raw.data() + static_cast<size_t>(count) * nq;   // after the count q's of nq each
        q[i] = Eigen::Map<Eigen::VectorXd>(raw.data() + static_cast<size_t>(i) * nq, nq);
        v[i] = Eigen::Map<Eigen::VectorXd>(vs + static_cast<size_t>(i) * n, n);
        a[i] = Eigen::Map<Eigen::VectorXd>(vs + static_cast<size_t>(count + i) * n, n);
    }
#ifdef TIME_DERIVATIVES
    const size_t block = static_cast<size_t>(3) * n * n;
    std::vector<double> tau(static_cast<size_t>(count) * block);
    using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    auto pass = [&]() {
        double sink = 0.0;
        for (int i = 0; i < count; ++i) {
            double *out = tau.data() + static_cast<size_t>(i) * block;
            Eigen::Map<RowMatrix> d_q(out, n, n), d_v(out + n * n, n, n), third(out + 2 * n * n, n, n);
            if (aba_derivatives) {
                pinocchio::computeABADerivatives(model, data, q[i], v[i], a[i]);
                d_q = data.ddq_dq;
                d_v = data.ddq_dv;
                third = data.Minv;
            } else {
                pinocchio::computeRNEADerivatives(model, data, q[i], v[i], a[i]);
                d_q = data.dtau_dq;
                d_v = data.dtau_dv;
                third = data.M;
            }
            third.triangularView<Eigen::StrictlyLower>() = third.transpose();
            sink += out[0];
        }
        return sink;
    };
#else
    std::vector<double> tau(static_cast<size_t>(count) * n);
    auto pass = [&]() {
        double sink = 0.0;
        for (int i = 0; i < count; ++i) {
#ifdef TIME_ABA
            pinocchio::aba(model, data, q[i], v[i], a[i]);
            const Eigen::VectorXd &result = data.ddq;
#else
            pinocchio::rnea(model, data, q[i], v[i], a[i]);
            const Eigen::VectorXd &result = data.tau;
#endif
            Eigen::Map<Eigen::VectorXd>(tau.data() + static_cast<size_t>(i) * n, n) = result;
            sink += result[0];
        }
        return sink;
    };
#endif
    const auto [median_ns, min_ns] = time_per_call(pass, count, repeats);
    std::printf("%.3f %.3f\n", median_ns, min_ns);
    f = std::fopen(argv[5], "wb");
    if (!f || std::fwrite(tau.data(), sizeof(double), tau.size(), f) != tau.size()) return 2;
    std::fclose(f);
    return 0;
}
