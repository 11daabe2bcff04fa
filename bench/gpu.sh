#!/usr/bin/env bash
# One prepared run on a machine with an NVIDIA GPU (under five minutes): install the GPU extra,
# build the kernels of the double pendulum, UR5, Panda and a random 16-link chain, check them
# against NAME_integrate_batch on the CPU, and print trajectory-steps per second of RK4 (h = 1 ms,
# 1,000 steps) on the GPU beside all of this machine's cores, then the Kapitza Floquet chart.
# Usage: bench/gpu.sh [TRAJECTORIES]  (default 2^20)
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
    $PY -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -e '.[gpu,sweep]'
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader || true
exec .venv/bin/python bench/gpu.py "${1:-1048576}"
