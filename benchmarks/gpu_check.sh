#!/usr/bin/env bash
# The one-shot check for a lent GPU machine (run it first when a session has one):
#   1. the CUDA training test (camera, curiosity and hybrid-action paths on the GPU, evaluation on the CPU);
#   2. every environment's training throughput with the policy on the device and the environments on the CPU
#      cores, as several concurrent runs when the machine has the cores for them (how a grid uses it),
#      merged into OUT/train_throughput.json (a copy of benchmarks/results/train_throughput.json).
#
#   bash benchmarks/gpu_check.sh [--device cuda|cpu] [--steps N] [--processes N] [--out DIR] [--env ID ...]
#                                [--set NAME=VALUE ...] [--no-mps]
#
# Several processes on one GPU time-slice it unless NVIDIA's Multi-Process Service runs: where
# nvidia-cuda-mps-control exists the script starts it for the throughput runs and stops it after (--no-mps
# does not). On one H100 with 16 cores (2026-11-26), Ocean Plastic Collection trained 9,832 agent-steps/s as
# 8 processes x 2 threads without MPS, 9,974 as 16 x 1 without it, and 26,107 as 16 x 1 with it.
#
# --device cpu runs the same steps without a GPU (the CUDA test is then skipped): CI tests the script so.
# Defaults: --device cuda, --steps 100000 agent-steps per run, --processes one per core on a GPU (1 on cpu),
# threads the cores over the processes, --out benchmarks/results, every environment. It stops at the first
# failure; the throughput rows measured before it are kept.
set -euo pipefail
cd "$(dirname "$0")/.."

device=cuda steps=100000 processes="" out=benchmarks/results mps=yes
sets=() envs=()
while [ $# -gt 0 ]; do
    case "$1" in
        --device) device="$2"; shift 2 ;;
        --steps) steps="$2"; shift 2 ;;
        --processes) processes="$2"; shift 2 ;;
        --out) out="$2"; shift 2 ;;
        --set) sets+=(--set "$2"); shift 2 ;;
        --env) envs+=(--env "$2"); shift 2 ;;
        --no-mps) mps=no; shift ;;
        *) echo "gpu_check.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
    esac
done
python="${PYTHON:-python3}"
cores=$(nproc)
if [ -z "$processes" ]; then
    if [ "$device" = cpu ]; then processes=1; else processes=$cores; fi
fi
threads=$(( cores / processes > 0 ? cores / processes : 1 ))
mkdir -p "$out"
if [ "$out/train_throughput.json" -ef benchmarks/results/train_throughput.json ]; then :; else
    cp benchmarks/results/train_throughput.json "$out/train_throughput.json"
fi

echo "== 1/2 the CUDA training test on $device"
if [ "$device" != cpu ]; then
    "$python" -c "import torch; assert torch.cuda.is_available(), 'torch sees no CUDA GPU'; \
print(torch.__version__, torch.cuda.get_device_name(0))"
fi
log=$(mktemp)
"$python" -m pytest -p no:cacheprovider -rs \
    "tests/train/test_train.py::test_training_on_cuda_updates_the_policy_and_evaluates_on_the_cpu" | tee "$log"
if [ "$device" != cpu ] && ! grep -q "1 passed" "$log"; then
    echo "gpu_check.sh: the CUDA training test did not pass on $device" >&2
    exit 1
fi

if [ "$device" != cpu ] && [ "$mps" = yes ] && command -v nvidia-cuda-mps-control >/dev/null; then
    export CUDA_MPS_PIPE_DIRECTORY="$(mktemp -d)" CUDA_MPS_LOG_DIRECTORY="$(mktemp -d)"
    nvidia-cuda-mps-control -d
    trap 'echo quit | nvidia-cuda-mps-control' EXIT
    echo "NVIDIA MPS started: the processes share the GPU instead of time-slicing it"
fi
echo "== 2/2 training throughput: $processes process(es) x $threads thread(s) per environment on $device"
PYTHONUNBUFFERED=1 "$python" benchmarks/train_throughput.py --steps "$steps" --processes "$processes" \
    --set device="$device" --set torch_threads="$threads" "${envs[@]}" "${sets[@]}" -o "$out/train_throughput.json"
echo "gpu_check.sh: done; rows in $out/train_throughput.json"
