// Pinocchio peer of bench/speed.py: reads the chain written by peers.pinocchio_data from the
// file named by BENCH_CHAIN (RX joints, placements, inertias about the centre of mass), then
// times forwardKinematics (for the angular velocities) + ABA with the gyrostat moments
// -omega x lambda as external forces in the joint frames.  Compiled once for every n.
#include "pinocchio_chain.h"
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/kinematics.hpp>

static int bench_qdd(const double *x, double *qdd)
{
    for (int i = 0; i < n_; ++i) {
        q_[i] = x[i];
        v_[i] = x[n_ + i];
    }
    pinocchio::forwardKinematics(*model_, *data_, q_, v_);
    for (int i = 0; i < n_; ++i) {
        const Eigen::Vector3d w = data_->v[i + 1].angular();
        (*fext_)[i + 1] = pinocchio::Force(Eigen::Vector3d::Zero(), -w.cross(lam_[i]));
    }
    const Eigen::VectorXd &a = pinocchio::aba(*model_, *data_, q_, v_, tau_, *fext_);
    for (int i = 0; i < n_; ++i) {
        qdd[i] = a[i];
    }
    return 0;
}

#include "harness.h"
