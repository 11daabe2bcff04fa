// The chain of bench/speed.py for Pinocchio, read from the file named by BENCH_CHAIN (written by
// peers.pinocchio_data): RX joints, placements, inertias about the centre of mass, gyrostatic
// moments.  Shared by pinocchio.cpp (ABA) and pinocchio_derivatives.cpp (computeABADerivatives).
#include <cstdio>
#include <cstdlib>
#include <pinocchio/spatial.hpp>
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/kinematics.hpp>

static pinocchio::Model *model_;
static pinocchio::Data *data_;
static pinocchio::container::aligned_vector<pinocchio::Force> *fext_;
static std::vector<Eigen::Vector3d> lam_;
static Eigen::VectorXd q_, v_, tau_;
static int n_;

static int bench_setup(void)
{
    const char *path = std::getenv("BENCH_CHAIN");
    FILE *fh = path ? std::fopen(path, "r") : nullptr;
    double g;
    if (!fh || std::fscanf(fh, "%d %lf", &n_, &g) != 2) {
        std::fprintf(stderr, "cannot read BENCH_CHAIN\n");
        std::exit(1);
    }
    model_ = new pinocchio::Model();
    pinocchio::JointIndex parent = 0;
    for (int k = 0; k < n_; ++k) {
        double v[28];
        for (int i = 0; i < 28; ++i) {
            if (std::fscanf(fh, "%lf", &v[i]) != 1) {
                std::fprintf(stderr, "short chain file\n");
                std::exit(1);
            }
        }
        Eigen::Matrix3d R, IG;
        R << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
        Eigen::Vector3d p(v[9], v[10], v[11]), c(v[13], v[14], v[15]);
        IG << v[16], v[17], v[18], v[19], v[20], v[21], v[22], v[23], v[24];
        parent = model_->addJoint(parent, pinocchio::JointModelRX(), pinocchio::SE3(R, p), "j" + std::to_string(k));
        model_->appendBodyToJoint(parent, pinocchio::Inertia(v[12], c, IG), pinocchio::SE3::Identity());
        lam_.push_back(Eigen::Vector3d(v[25], v[26], v[27]));
    }
    std::fclose(fh);
    model_->gravity.linear(Eigen::Vector3d(g, 0.0, 0.0));
    data_ = new pinocchio::Data(*model_);
    fext_ = new pinocchio::container::aligned_vector<pinocchio::Force>(model_->njoints, pinocchio::Force::Zero());
    q_.resize(n_);
    v_.resize(n_);
    tau_ = Eigen::VectorXd::Zero(n_);
    return n_;
}

