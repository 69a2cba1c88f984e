#!/usr/bin/env bash
# The GPU figures of docs/performance.md in one run, on a machine with a GPU (it may be lent
# for minutes only): the GPU backend in single and double precision and the CPU step of the
# same machine on the same cases, with the machine described and each kernel's share of the
# GPU step. Everything it needs is prepared beforehand; it builds nothing and reaches nothing
# outside the machine.
#
#   docs/gpu-bench.sh [OUT]        # OUT: the folder for the results (default out/gpu-bench)
#
# Environment:
#   SLOSH    the slosh binary (default target/release/slosh, built here with
#            `cargo build --release -p slosh-cli` and carried to the GPU machine)
#   CASES    bench cases (default 2d-80k,3d-500k,3d-1m,3d-real: the 2D 80k and the 3D 500k and
#            1M particle cylinders, and the real-scale tank at 24 particles per radius)
#   LIMIT_S  time limit of each bench command in seconds (default 120)
#
# Writes OUT/machine.txt (GPU, driver, CPU, cores, slosh version), OUT/gpu_f32_CASE/bench_gpu.csv
# and OUT/gpu_CASE/bench_gpu.csv for each case (particle-steps/s, wall time per simulated
# second, device, kernel shares) and OUT/cpu/bench.csv (the modern preset on the CPU, all cores), and a log
# of each command. A command that fails or runs out of time is reported and the others still
# run; the exit status is non-zero if any failed.
#
# The Vulkan loader: a machine whose `ldconfig -p | grep libvulkan` prints nothing needs the
# loader brought along (Debian's libvulkan1 unpacked into / before the run); with an NVIDIA
# driver that Vulkan does not find, set VK_DRIVER_FILES to its ICD file
# (e.g. /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json).
set -uo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
SLOSH="${SLOSH:-target/release/slosh}"
OUT="${1:-out/gpu-bench}"
CASES="${CASES:-2d-80k,3d-500k,3d-1m,3d-real}"
LIMIT_S="${LIMIT_S:-120}"
if [ ! -x "$SLOSH" ]; then
    echo "error: no slosh binary at $SLOSH: build it with \`cargo build --release -p slosh-cli\` (or set SLOSH)" >&2
    exit 1
fi
mkdir -p "$OUT"

{
    echo "date (UTC): $(date -u '+%Y-%m-%d %H:%M:%S')"
    echo "slosh: $("$SLOSH" --version 2>&1)"
    echo "host: $(uname -srm)"
    echo "cores: $(nproc)"
    grep -m1 'model name' /proc/cpuinfo 2>/dev/null || true
    echo "--- nvidia-smi"
    nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv 2>&1 || echo "(no nvidia-smi)"
    echo "--- vulkan loader"
    ldconfig -p 2>/dev/null | grep libvulkan || echo "(no libvulkan in ldconfig)"
} > "$OUT/machine.txt"
cat "$OUT/machine.txt"

failed=0
# step NAME COMMAND...: one bench command with its time limit and its log.
step() {
    local name="$1"
    shift
    echo "=== $name: $*"
    if timeout "$LIMIT_S" "$@" > "$OUT/$name.log" 2>&1; then
        tail -n 20 "$OUT/$name.log"
    else
        echo "error: $name failed or ran out of its ${LIMIT_S} s (exit $?); its log: $OUT/$name.log" >&2
        tail -n 20 "$OUT/$name.log" >&2
        failed=1
    fi
}

# One command per case and precision: a case that runs out of its time keeps the others'
# results (bench_gpu.csv is written when its command ends).
for case in ${CASES//,/ }; do
    step "gpu_f32_$case" "$SLOSH" bench --backend gpu_f32 --case "$case" --out "$OUT/gpu_f32_$case"
    step "gpu_$case" "$SLOSH" bench --backend gpu --case "$case" --out "$OUT/gpu_$case"
done
step cpu "$SLOSH" bench --scheme modern --case "$CASES" --threads "$(nproc)" --out "$OUT/cpu"
exit "$failed"
