/* What a kernel takes from the model around it, declared so that a compiler reads a kernel file
 * as it stands (tests/models/test_kernels_compile.py, for each value of the flags): the generated header's codes and types, and the
 * model's own functions.  Never emitted: the generator prints the kernel's body after @kernel. */
#ifndef MODEL_STUB_H
#define MODEL_STUB_H
#include <math.h>

/* the model's facts (printers/c.py sets them per model) */
#ifndef MODEL_HAS_PARAMS
#define MODEL_HAS_PARAMS 1
#endif
#ifndef MODEL_NEWTON
#define MODEL_NEWTON 1
#endif
#ifndef MODEL_CANONICAL
#define MODEL_CANONICAL 1
#endif
#define MODEL_CANONICAL_NEWTON (MODEL_CANONICAL && MODEL_NEWTON)
#ifndef MODEL_VARIATIONAL
#define MODEL_VARIATIONAL 1
#endif
#define MODEL_FN  /* the header's function qualifier: __host__ __device__ under CUDA */
#define MODEL_RESTRICT_ restrict  /* the template's: restrict in C, __restrict__ in g++ */
#ifndef MODEL_PARAM_DERIVATIVES
#define MODEL_PARAM_DERIVATIVES 1
#endif
#ifndef MODEL_HESSIAN
#define MODEL_HESSIAN 1
#endif
#ifndef MODEL_LANES
#define MODEL_LANES 1
#endif
#ifndef MODEL_TIME_DEPENDENT
#define MODEL_TIME_DEPENDENT 0
#endif
#if MODEL_TIME_DEPENDENT && MODEL_CANONICAL
#error "Hamilton's variables exist only for an autonomous model (assemble.canonical_applies)"
#endif
#if MODEL_TIME_DEPENDENT
#define MODEL_T(...) __VA_ARGS__
#define MODEL_T_OR(a, b) a
#else
#define MODEL_T(...)
#define MODEL_T_OR(a, b) b
#endif

/* the model's numbers (a chain of two here): sizes and op counts */
#define MODEL_V_N 2
#define MODEL_V_DIM 4
#define MODEL_V_NN 4
#define MODEL_V_NU 1
#define MODEL_V_NNU1 2
#define MODEL_V_HCOL 5
#define MODEL_V_COLS (6 + MODEL_TIME_DEPENDENT)
#define MODEL_V_ZDIM (5 + MODEL_TIME_DEPENDENT)
#define MODEL_V_NP 2
#define MODEL_V_NNP 4
#define MODEL_V_DIM2 16
#define MODEL_V_2DIM 8
#define MODEL_V_4DIM2 64
#define MODEL_V_VDIM 20
#define MODEL_V_OPS_QDD 30
#define MODEL_V_OPS_QDD_DERIVATIVES 300
#define MODEL_V_OPS_VELOCITIES 40
#define MODEL_V_OPS_PDOT 20
#define MODEL_V_OPS_CANONICAL 60
#define MODEL_V_NEWTON_SWEEPS 20
#define MODEL_V_NEWTON_SWEEPS_CANONICAL 30
#define MODEL_V_LANES 8

/* the header's codes (codes.py) */
#define MODEL_OK 0
#define MODEL_SINGULAR 1
#define MODEL_NONFINITE 2
#define MODEL_NO_PARAMS 3
#define MODEL_SEPARATRIX 4
#define MODEL_NO_PERIOD 5
#define MODEL_QUAD_FAILED 6
#define MODEL_LIBRATION 1
#define MODEL_ROTATION 2
#define MODEL_STEADY 3
#define MODEL_STEP_UNDERFLOW 7
#define MODEL_NO_CONVERGENCE 8
#define MODEL_TOO_MANY_STEPS 9
#define MODEL_BAD_ARGUMENT 10
#define MODEL_RK4 1
#define MODEL_DOP853 2
#define MODEL_GAUSS2 3
#define MODEL_GAUSS2_FIXED 4
#define MODEL_GAUSS2_SYMPLECTIC 5
#define MODEL_RK4_LANES 6
#define MODEL_SEPARATRIX_TOL 1e-14

typedef struct model_params {
    double unused_;
} model_params;

typedef struct model_quad_info {
    int kind;
    double E;
    double k;
    double phi_min;
    double phi_max;
    double period;
    double psi_advance;
    double separatrix_distance;
} model_quad_info;

int model_quad_motion(const double *x0, const model_params *p, model_quad_info *info);
int model_quad_period(const double *x0, const model_params *p, double *period);
int model_quad_state(double t, const double *x0, const model_params *p, double *x);
int model_quad_functions(double phi, const double *x0, const model_params *p, double *out);
typedef struct model_integrate_stats {
    double t;
    double x[MODEL_V_DIM];
    long n_rhs;
    long n_steps;
    long n_rejected;
    long n_iter;
    long n_newton;
} model_integrate_stats;

int model_rhs(double t, const double *x, const double *u, const model_params *p, double *xdot);
int model_qdd_derivatives(MODEL_T(double t, )const double *x, const double *u, const model_params *p,
                          double *qdd, double *dqdd_dphi, double *dqdd_dphidot, double *dqdd_du);
int model_momenta(const double *x, const model_params *p, double *pm);
int model_velocities(const double *q, const double *pm, const model_params *p, double *qd);
int model_pdot(const double *x, const double *u, const model_params *p, double *pdot);
int model_integrate(int method, double t0, double t1, double h, double rtol, double atol,
                    const double *x0, const double *u, const model_params *p, double *x1, long *n_rhs);
int model_integrate_grid(int method, int nt, const double *t, double h, double rtol, double atol,
                         long max_steps, const double *x0, const double *u, const model_params *p,
                         double *X, model_integrate_stats *stats);
int model_integrate_batch(int method, int nb, int nt, const double *t, double h, double rtol, double atol,
                          long max_steps, const double *x0, const double *u, long u_stride,
                          const model_params *p, long p_stride, double *X, int *codes);
int model_integrate_variational(double t0, double t1, double h, double rtol, double atol,
                                const double *x0, const double *u, const model_params *p,
                                double *x1, double *Phi, model_integrate_stats *stats);
int model_step(double t, const double *x, const double *u, const model_params *p, double h, double *xn);
int model_step_jacobian(double t, const double *x, const double *u, const model_params *p, double h, double *xn,
                        double *Ad, double *Bd, double *xn_h MODEL_T(, double *xn_t));
int model_time_derivative(double t, const double *x, const double *u, const model_params *p, double *qdd, double *dqdd_dt);
int model_param_derivatives(MODEL_T(double t, )const double *x, const double *u, const model_params *p, double *qdd,
                            double *dqdd_dp);
int model_step_param_derivatives(double t, const double *x, const double *u, const model_params *p, double h, double *xn,
                                 double *dxn_dp);
int model_rhs_hessian(double t, const double *x, const double *u, const model_params *p, const double *lam, double *H);
int model_step_hessian(double t, const double *x, const double *u, const model_params *p, double h, const double *lam,
                       double *H);
/* the right side for RK4's lanes (the template prints them static, before kernels/integrate.c) */
void model_rhs_lane_(MODEL_T(double t, )int own, const double *X, const double *u, const model_params *p, double *XD,
                     int *code);
void model_rhs_lanes_(MODEL_T(double t, )int own, const double *X, const double *u, const model_params *p, double *XD,
                      int *code);
double model_energy(const double *x, const model_params *p);
double model_momentum(const double *x, const model_params *p);
static int model_all_finite_(const double *v, int count)
{
    int i;
    for (i = 0; i < count; ++i) {
        if (!isfinite(v[i])) {
            return 0;
        }
    }
    return 1;
}
#endif
