// Pinocchio peer of bench/robots.py: the model built by Pinocchio's own URDF parser from the file
// named by BENCH_URDF, the joints named in BENCH_LOCKS ("name value" lines) removed at their
// values (buildReducedModel), gravity 9.81 along -z; times ABA with the joint damping of
// BENCH_DAMPING (one number per joint) as the torque -b v (Pinocchio's ABA has no damping).
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>
#include <pinocchio/parsers/urdf.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/model.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>

static pinocchio::Model *model_;
static pinocchio::Data *data_;
static Eigen::VectorXd q_, v_, tau_, b_;
static int n_;

static int bench_setup(void)
{
    const char *urdf = std::getenv("BENCH_URDF"), *locks = std::getenv("BENCH_LOCKS"), *damp = std::getenv("BENCH_DAMPING");
    if (!urdf || !locks || !damp) {
        std::fprintf(stderr, "BENCH_URDF, BENCH_LOCKS, BENCH_DAMPING\n");
        std::exit(1);
    }
    pinocchio::Model full;
    pinocchio::urdf::buildModel(std::string(urdf), full);
    Eigen::VectorXd q0 = pinocchio::neutral(full);
    std::vector<pinocchio::JointIndex> drop;
    std::ifstream lf(locks);
    std::string name;
    double value;
    while (lf >> name >> value) {
        const pinocchio::JointIndex j = full.getJointId(name);
        q0[full.joints[j].idx_q()] = value;
        drop.push_back(j);
    }
    model_ = new pinocchio::Model(drop.empty() ? full : pinocchio::buildReducedModel(full, drop, q0));
    data_ = new pinocchio::Data(*model_);
    n_ = model_->nv;
    q_ = pinocchio::neutral(*model_);
    v_ = tau_ = b_ = Eigen::VectorXd::Zero(n_);
    std::ifstream df(damp);
    for (int i = 0; i < n_; ++i) {
        df >> b_[i];
    }
    return n_;
}

static int bench_qdd(const double *x, double *qdd)
{
    for (int i = 0; i < n_; ++i) {
        q_[i] = x[i];
        v_[i] = x[n_ + i];
        tau_[i] = -b_[i] * x[n_ + i];
    }
    const Eigen::VectorXd &a = pinocchio::aba(*model_, *data_, q_, v_, tau_);
    for (int i = 0; i < n_; ++i) {
        qdd[i] = a[i];
    }
    return 0;
}

#include "harness.h"
