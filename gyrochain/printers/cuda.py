"""The CUDA target (``generate --gpu``): NAME_gpu.cu, kernels of one thread per trajectory that run
the integrators of NAME.c (every function of it NAME_FN, __host__ __device__ under CUDA).  The
kernels are written in NAME_REAL, so the file is the same for a double and a float build."""
from __future__ import annotations


class CudaTarget:
    """Lays out the kernels of NAME_gpu.cu for the model (which of them exist is the C's facts:
    NAME_integrate_variational up to VARIATIONAL_MAX_N joints)."""

    suffixes = ("_gpu.cu",)

    def files(self, model, context: dict, env) -> dict[str, str]:
        name = model.spec.name
        return {f"{name}_gpu.cu": env.get_template("model_gpu.cu.jinja").render(context)}
