"""The GPU: a model's NAME_gpu.cu (``generate --gpu``) compiled by NVRTC and launched through CuPy,
one thread per trajectory, behind the same ``integrate_batch`` and ``integrate_variational`` calls
as the compiled C model, so that a sweep writes the same store on either (``sweep --device cuda``).

May import: ``models`` and below (the pipeline's files and cache), never the commands.
"""
from .device import (GpuModel, GpuUnavailable, NVRTC_HEADERS, compile_ptx, gpu_model, nvrtc_library,  # noqa: F401
                     nvrtc_version, ptxas_report, unavailable)
