// Single-call timing of Pinocchio's constrained forward dynamics (used by constrained_forward.py).
//
// The robot is a symgen scene's spanning tree as symgen.oracle.pinocchio_tree builds it in Python,
// written by constrained_forward.py as text and rebuilt here with addJoint / appendBodyToJoint /
// addFrame, so every Pinocchio template is compiled with this file's flags (header only):
//   nq nv njoints
//   per joint: parent type ax ay az R(9, row-major) p(3) mass c(3) Ixx Ixy Iyy Ixz Iyz Izz
//     (type: a code of pinocchio_joints.hpp, e.g. RZ PZ S, FF for a floating base; a: the axis of RU, PU)
//   armature(nv)  damping(nv)  coulomb(nv)  gravity(3)    (friction b v + c sign(v), eq. 22)
//   nconstraints, per constraint: type(6: CONTACT_6D, 3: CONTACT_3D, 0: none) joint_a R_a(9) p_a(3)
//     joint_b R_b(9) p_b(3) ncomp comp(ncomp; 0..5 = vx vy vz wx wy wz)
//   motion: 0 m idx(m)  (joint accelerations at these velocity indices), or
//           1 nframes {joint R(9) p(3) weight}(nframes) ncomp comp(ncomp)  (weighted frame rates)
//   contact forces eta_m: ncomp (0: none) [joint R(9) p(3) comp(ncomp)]
// MODE:
//   cd   constraintDynamics (initConstraintDynamics outside the loop, ProximalSettings mu = 0,
//        one iteration: the exact KKT solve), then dV_m from ddq (forwardKinematics + frame
//        acceleration, or the joint accelerations); multipliers written as -lambda_c
//   kkt  forwardKinematics(q, v, 0), computeJointJacobians, frame Jacobians and drifts, crba,
//        nonLinearEffects, then the (nv + nc) KKT system solved by Eigen's PartialPivLU
//   aba  aba (no constraint)
//   cdd  cd, then computeConstraintDynamicsDerivatives (the partials of ddq and lambda_c in q, v, tau
//        into Data); the same outputs as cd
// STATES: float64 q[COUNT][nq], v[COUNT][nv], tau[COUNT][nv], eta_m[COUNT][ncontact]
// Usage: ./constrained MODEL MODE STATES COUNT REPEATS OUT
//   prints "median_ns min_ns" per call; writes dV_m[COUNT][m] and multipliers[COUNT][nc] to OUT.
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/constrained-dynamics.hpp>
#include <pinocchio/algorithm/constrained-dynamics-derivatives.hpp>
#include <pinocchio/constraints.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>

#include <Eigen/LU>

#include "pinocchio_joints.hpp"
#include "thread_timer.hpp"

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

using pinocchio::FrameIndex;
using pinocchio::JointIndex;
using Mat6x = Eigen::Matrix<double, 6, Eigen::Dynamic>;

struct Constraint {
    int type;
    FrameIndex a, b;     // frames on the two bodies (b = 0: the world)
    std::vector<int> comp;
};

struct Robot {
    pinocchio::Model model;
    std::vector<Constraint> constraints;
    std::vector<pinocchio::RigidConstraintModel> cmodels;
    Eigen::VectorXd damping, coulomb;
    bool motion_frames = false;
    std::vector<int> motion_idx;               // joint motion
    std::vector<FrameIndex> motion_frame;      // frame motion
    std::vector<double> motion_weight;
    std::vector<int> motion_comp;
    FrameIndex contact = 0;
    std::vector<int> contact_comp;
    int nc = 0, m = 0;
};

[[noreturn]] static void fail(const std::string &what)
{
    std::fprintf(stderr, "%s\n", what.c_str());
    std::exit(2);
}

static pinocchio::SE3 read_se3(std::istream &in)
{
    Eigen::Matrix3d r;
    Eigen::Vector3d p;
    for (int k = 0; k < 9; ++k) in >> r(k / 3, k % 3);
    in >> p[0] >> p[1] >> p[2];
    return pinocchio::SE3(r, p);
}

static std::vector<int> read_ints(std::istream &in)
{
    int n = 0;
    in >> n;
    std::vector<int> out(n);
    for (int &x : out) in >> x;
    return out;
}

static FrameIndex add_frame(pinocchio::Model &model, JointIndex joint, const pinocchio::SE3 &placement)
{
    const std::string name = "f" + std::to_string(model.nframes);
    return model.addFrame(pinocchio::Frame(name, joint, placement, pinocchio::OP_FRAME));
}

static Robot read_robot(const char *path)
{
    std::ifstream in(path);
    int nq = 0, nv = 0, joints = 0;
    if (!(in >> nq >> nv >> joints)) fail(std::string("cannot read ") + path);
    Robot robot;
    pinocchio::Model &model = robot.model;
    for (int i = 1; i <= joints; ++i) {
        int parent;
        std::string type;
        Eigen::Vector3d axis;
        in >> parent >> type >> axis[0] >> axis[1] >> axis[2];
        pinocchio::SE3 placement = read_se3(in);
        double mass, ixx, ixy, iyy, ixz, iyz, izz;
        Eigen::Vector3d c;
        in >> mass >> c[0] >> c[1] >> c[2] >> ixx >> ixy >> iyy >> ixz >> iyz >> izz;
        if (!in) fail("bad joint " + std::to_string(i));
        const std::string name = "j" + std::to_string(i);
        const JointIndex p = static_cast<JointIndex>(parent);
        const JointIndex id = add_joint(model, p, type, axis, placement, name);
        Eigen::Matrix3d inertia;
        inertia << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
        model.appendBodyToJoint(id, pinocchio::Inertia(mass, c, inertia), pinocchio::SE3::Identity());
    }
    if (model.nq != nq || model.nv != nv) fail("nq/nv mismatch");
    for (int k = 0; k < nv; ++k) in >> model.armature[k];
    robot.damping.resize(nv);
    robot.coulomb.resize(nv);
    for (int k = 0; k < nv; ++k) in >> robot.damping[k];
    for (int k = 0; k < nv; ++k) in >> robot.coulomb[k];
    Eigen::Vector3d g;
    in >> g[0] >> g[1] >> g[2];
    model.gravity = pinocchio::Motion(g, Eigen::Vector3d::Zero());
    int ncon = 0;
    in >> ncon;
    for (int k = 0; k < ncon; ++k) {
        Constraint con;
        int ja, jb;
        in >> con.type >> ja;
        pinocchio::SE3 xa = read_se3(in);
        in >> jb;
        pinocchio::SE3 xb = read_se3(in);
        con.comp = read_ints(in);
        con.a = add_frame(model, static_cast<JointIndex>(ja), xa);
        con.b = jb == 0 ? 0 : add_frame(model, static_cast<JointIndex>(jb), xb);
        robot.nc += static_cast<int>(con.comp.size());
        robot.constraints.push_back(con);
        if (con.type == 6 || con.type == 3)
            robot.cmodels.emplace_back(con.type == 6 ? pinocchio::CONTACT_6D : pinocchio::CONTACT_3D, model,
                                       static_cast<JointIndex>(ja), xa, static_cast<JointIndex>(jb), xb,
                                       pinocchio::LOCAL);
    }
    int kind = 0;
    in >> kind;
    if (kind == 0) {
        robot.motion_idx = read_ints(in);
        robot.m = static_cast<int>(robot.motion_idx.size());
    } else {
        robot.motion_frames = true;
        int nf = 0;
        in >> nf;
        for (int k = 0; k < nf; ++k) {
            int j;
            in >> j;
            pinocchio::SE3 x = read_se3(in);
            double w;
            in >> w;
            robot.motion_frame.push_back(add_frame(model, static_cast<JointIndex>(j), x));
            robot.motion_weight.push_back(w);
        }
        robot.motion_comp = read_ints(in);
        robot.m = static_cast<int>(robot.motion_comp.size());
    }
    int ncontact = 0;
    in >> ncontact;
    if (ncontact > 0) {
        int j;
        in >> j;
        pinocchio::SE3 x = read_se3(in);
        robot.contact = add_frame(model, static_cast<JointIndex>(j), x);
        for (int k = 0; k < ncontact; ++k) {
            int c;
            in >> c;
            robot.contact_comp.push_back(c);
        }
    }
    if (!in) fail("truncated model file");
    return robot;
}

// Rows S (J_A - Ad(A^-1) J_B^world) and drift S (a_A - Ad(A^-1) a_B^world + v_A x Ad(A^-1) v_B^world)
// of one constraint, from forwardKinematics(q, v, 0) and computeJointJacobians (as symgen.oracle).
static void constraint_rows(const pinocchio::Model &model, pinocchio::Data &data, const Constraint &con,
                            Mat6x &ja, Mat6x &jb, Eigen::Ref<Eigen::MatrixXd> rows, Eigen::Ref<Eigen::VectorXd> gamma)
{
    ja.setZero();
    pinocchio::updateFramePlacement(model, data, con.a);
    pinocchio::getFrameJacobian(model, data, con.a, pinocchio::LOCAL, ja);
    const pinocchio::Motion va = pinocchio::getFrameVelocity(model, data, con.a, pinocchio::LOCAL);
    Eigen::Matrix<double, 6, 1> g = pinocchio::getFrameAcceleration(model, data, con.a, pinocchio::LOCAL).toVector();
    if (con.b != 0) {
        jb.setZero();
        pinocchio::updateFramePlacement(model, data, con.b);
        pinocchio::getFrameJacobian(model, data, con.b, pinocchio::WORLD, jb);
        const pinocchio::SE3 a_inv = data.oMf[con.a].inverse();
        ja.noalias() -= a_inv.toActionMatrix() * jb;
        const pinocchio::Motion vb = a_inv.act(pinocchio::getFrameVelocity(model, data, con.b, pinocchio::WORLD));
        const pinocchio::Motion ab = a_inv.act(pinocchio::getFrameAcceleration(model, data, con.b, pinocchio::WORLD));
        g += -ab.toVector() + va.cross(vb).toVector();
    }
    for (size_t k = 0; k < con.comp.size(); ++k) {
        rows.row(static_cast<Eigen::Index>(k)) = ja.row(con.comp[k]);
        gamma[static_cast<Eigen::Index>(k)] = g[con.comp[k]];
    }
}

int main(int argc, char **argv)
{
    if (argc != 7) fail("usage: constrained MODEL MODE STATES COUNT REPEATS OUT");
    Robot robot = read_robot(argv[1]);
    const std::string mode = argv[2];
    const int count = std::atoi(argv[4]), repeats = std::atoi(argv[5]);
    pinocchio::Model &model = robot.model;
    const int nq = model.nq, nv = model.nv, nc = robot.nc, m = robot.m;
    const int ne = static_cast<int>(robot.contact_comp.size());
    pinocchio::Data data(model);

    const size_t per = static_cast<size_t>(nq + 2 * nv + ne);
    std::vector<double> raw(per * static_cast<size_t>(count));
    FILE *f = std::fopen(argv[3], "rb");
    if (!f || std::fread(raw.data(), sizeof(double), raw.size(), f) != raw.size()) fail("cannot read states");
    std::fclose(f);
    std::vector<Eigen::VectorXd> q(count), v(count), tau(count), eta(count);
    const double *base = raw.data();
    for (int i = 0; i < count; ++i) q[i] = Eigen::Map<const Eigen::VectorXd>(base + static_cast<size_t>(i) * nq, nq);
    base += static_cast<size_t>(count) * nq;
    for (int i = 0; i < count; ++i) v[i] = Eigen::Map<const Eigen::VectorXd>(base + static_cast<size_t>(i) * nv, nv);
    base += static_cast<size_t>(count) * nv;
    for (int i = 0; i < count; ++i) tau[i] = Eigen::Map<const Eigen::VectorXd>(base + static_cast<size_t>(i) * nv, nv);
    base += static_cast<size_t>(count) * nv;
    for (int i = 0; i < count; ++i) eta[i] = Eigen::Map<const Eigen::VectorXd>(base + static_cast<size_t>(i) * ne, ne);

    std::vector<double> out(static_cast<size_t>(count) * (m + nc), 0.0);
    // workspaces, allocated once
    std::vector<pinocchio::RigidConstraintData> cdatas;
    for (const auto &cm : robot.cmodels) cdatas.emplace_back(cm);
    pinocchio::ProximalSettings settings(1e-14, 0.0, 1);
    if (mode == "cd" || mode == "cdd") {
        if (static_cast<int>(robot.cmodels.size()) != static_cast<int>(robot.constraints.size()))
            fail("modes cd and cdd need every constraint to be a CONTACT_6D or CONTACT_3D");
        pinocchio::initConstraintDynamics(model, data, robot.cmodels, cdatas);
    }
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(nv);
    Mat6x ja(6, nv), jb(6, nv), jf(6, nv);
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(nv + nc, nv + nc);
    Eigen::VectorXd rhs(nv + nc), sol(nv + nc), drift = Eigen::VectorXd::Zero(m);
    Eigen::MatrixXd jm = Eigen::MatrixXd::Zero(m, nv), jc(ne, nv);
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(nv + nc);
    Eigen::VectorXd ddq(nv), dvm(m), mult(nc), teff(nv);

    // dV_m = sum_f w_f S (J_f ddq + a_f(q, v, 0)): rows and drift of the motion frames
    auto motion_rows = [&]() {
        jm.setZero();
        drift.setZero();
        for (size_t k = 0; k < robot.motion_frame.size(); ++k) {
            jf.setZero();
            pinocchio::getFrameJacobian(model, data, robot.motion_frame[k], pinocchio::LOCAL, jf);
            const auto a0 = pinocchio::getFrameAcceleration(model, data, robot.motion_frame[k], pinocchio::LOCAL).toVector();
            for (size_t c = 0; c < robot.motion_comp.size(); ++c) {
                jm.row(static_cast<Eigen::Index>(c)) += robot.motion_weight[k] * jf.row(robot.motion_comp[c]);
                drift[static_cast<Eigen::Index>(c)] += robot.motion_weight[k] * a0[robot.motion_comp[c]];
            }
        }
    };
    auto motion_from_ddq = [&](int i) {
        if (!robot.motion_frames) {
            for (int c = 0; c < m; ++c) dvm[c] = ddq[robot.motion_idx[static_cast<size_t>(c)]];
            return;
        }
        if (mode == "kkt") {
            dvm.noalias() = jm * ddq + drift;
            return;
        }
        pinocchio::forwardKinematics(model, data, q[i], v[i], ddq);
        dvm.setZero();
        for (size_t k = 0; k < robot.motion_frame.size(); ++k) {
            const auto a = pinocchio::getFrameAcceleration(model, data, robot.motion_frame[k], pinocchio::LOCAL).toVector();
            for (size_t c = 0; c < robot.motion_comp.size(); ++c)
                dvm[static_cast<Eigen::Index>(c)] += robot.motion_weight[k] * a[robot.motion_comp[c]];
        }
    };
    auto solve = [&](int i) {
        // joint friction, which Pinocchio's algorithms leave out, moved to the applied side
        teff = tau[i] - robot.damping.cwiseProduct(v[i]) - robot.coulomb.cwiseProduct(v[i].cwiseSign());
        if (mode == "aba") {
            ddq = pinocchio::aba(model, data, q[i], v[i], teff);
        } else if (mode == "cd" || mode == "cdd") {
            ddq = pinocchio::constraintDynamics(model, data, q[i], v[i], teff, robot.cmodels, cdatas, settings);
            mult = -data.lambda_c;
            if (mode == "cdd")
                pinocchio::computeConstraintDynamicsDerivatives(model, data, robot.cmodels, cdatas, settings);
        } else {
            pinocchio::forwardKinematics(model, data, q[i], v[i], zero);
            pinocchio::computeJointJacobians(model, data);
            Eigen::Index row = 0;
            for (const auto &con : robot.constraints) {
                const Eigen::Index k = static_cast<Eigen::Index>(con.comp.size());
                constraint_rows(model, data, con, ja, jb, kkt.block(nv + row, 0, k, nv), rhs.segment(nv + row, k));
                row += k;
            }
            rhs.tail(nc) = -rhs.tail(nc);
            if (robot.motion_frames) motion_rows();
            rhs.head(nv) = teff;
            if (ne) {
                jf.setZero();
                pinocchio::getFrameJacobian(model, data, robot.contact, pinocchio::LOCAL, jf);
                for (int c = 0; c < ne; ++c) jc.row(c) = jf.row(robot.contact_comp[static_cast<size_t>(c)]);
                rhs.head(nv).noalias() -= jc.transpose() * eta[i];
            }
            pinocchio::crba(model, data, q[i]);
            data.M.triangularView<Eigen::StrictlyLower>() = data.M.transpose().triangularView<Eigen::StrictlyLower>();
            rhs.head(nv) -= pinocchio::nonLinearEffects(model, data, q[i], v[i]);
            kkt.topLeftCorner(nv, nv) = data.M;
            kkt.topRightCorner(nv, nc) = kkt.bottomLeftCorner(nc, nv).transpose();
            lu.compute(kkt);
            sol.noalias() = lu.solve(rhs);
            ddq = sol.head(nv);
            mult = sol.tail(nc);
        }
        motion_from_ddq(i);
        double *o = out.data() + static_cast<size_t>(i) * (m + nc);
        Eigen::Map<Eigen::VectorXd>(o, m) = dvm;
        if (mode != "aba") Eigen::Map<Eigen::VectorXd>(o + m, nc) = mult;
        return o[0];
    };
    auto pass = [&]() {
        double sink = 0.0;
        for (int i = 0; i < count; ++i) sink += solve(i);
        return sink;
    };
    const auto [median_ns, min_ns] = time_per_call(pass, count, repeats);
    std::printf("%.3f %.3f\n", median_ns, min_ns);
    f = std::fopen(argv[6], "wb");
    if (!f || std::fwrite(out.data(), sizeof(double), out.size(), f) != out.size()) fail("cannot write output");
    std::fclose(f);
    return 0;
}
