// Joints of a Pinocchio model rebuilt from text by the C++ timing harnesses (rnea_timing.cpp,
// constrained_timing.cpp): a type code and, for the unaligned kinds, an axis.
//   RX RY RZ RU   revolute about x, y, z, or the axis a (U: unaligned)
//   PX PY PZ PU   prismatic along x, y, z, or the axis a
//   S             spherical
//   FF            free flyer (a floating base)
#pragma once

#include <pinocchio/multibody.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

static pinocchio::JointIndex add_joint(pinocchio::Model &model, pinocchio::JointIndex parent, const std::string &type,
                                        const Eigen::Vector3d &axis, const pinocchio::SE3 &placement,
                                        const std::string &name)
{
    if (type == "RX") return model.addJoint(parent, pinocchio::JointModelRX(), placement, name);
    if (type == "RY") return model.addJoint(parent, pinocchio::JointModelRY(), placement, name);
    if (type == "RZ") return model.addJoint(parent, pinocchio::JointModelRZ(), placement, name);
    if (type == "RU") return model.addJoint(parent, pinocchio::JointModelRevoluteUnaligned(axis), placement, name);
    if (type == "PX") return model.addJoint(parent, pinocchio::JointModelPX(), placement, name);
    if (type == "PY") return model.addJoint(parent, pinocchio::JointModelPY(), placement, name);
    if (type == "PZ") return model.addJoint(parent, pinocchio::JointModelPZ(), placement, name);
    if (type == "PU") return model.addJoint(parent, pinocchio::JointModelPrismaticUnaligned(axis), placement, name);
    if (type == "S") return model.addJoint(parent, pinocchio::JointModelSpherical(), placement, name);
    if (type == "FF") return model.addJoint(parent, pinocchio::JointModelFreeFlyer(), placement, name);
    std::fprintf(stderr, "unknown joint type %s\n", type.c_str());
    std::exit(2);
}
