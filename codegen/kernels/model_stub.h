/* What a kernel takes from the model around it, declared so that a compiler reads a kernel file
 * as it stands (tests/models/test_kernels.py): the generated header's codes and types, and the
 * model's own functions.  Never emitted: the generator prints the kernel's body after @kernel. */
#ifndef MODEL_STUB_H
#define MODEL_STUB_H
#include <math.h>

#ifndef MODEL_HAS_PARAMS
#define MODEL_HAS_PARAMS 1
#endif
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
