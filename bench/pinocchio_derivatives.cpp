// Pinocchio peer of bench/derivatives.py: computeABADerivatives (Carpentier & Mansard 2018), the
// analytical derivatives of the articulated-body algorithm, on the chain of pinocchio_chain.h.
// Its derivatives do not see external forces that depend on the state, so the benchmark gives it
// the chain with lambda = 0 (the gyrostatic moment -omega x lambda is such a force).
#include "pinocchio_chain.h"
#include <pinocchio/algorithm/aba-derivatives.hpp>

#define BENCH_NOUT(n) ((n) * 2 * (n))

static int bench_qdd(const double *x, double *out)
{
    for (int i = 0; i < n_; ++i) {
        q_[i] = x[i];
        v_[i] = x[n_ + i];
    }
    pinocchio::computeABADerivatives(*model_, *data_, q_, v_, tau_);
    for (int i = 0; i < n_; ++i) {
        for (int j = 0; j < n_; ++j) {
            out[i * 2 * n_ + j] = data_->ddq_dq(i, j);
            out[i * 2 * n_ + n_ + j] = data_->ddq_dv(i, j);
        }
    }
    return 0;
}

#include "harness.h"
