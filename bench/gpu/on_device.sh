#!/usr/bin/env bash
# make bench-gpu on a lent GPU machine (issue 27): no Rust toolchain, no network, minutes of time.
#
# Prepared here, run there, in the repository root of a copy of the working tree:
#   .devbin/  the stripped release binaries built here: gpu_bench (the core's benchmark),
#             gpu_solver and core_lib (the GPU test suite: tests/gpu_solver.rs and the lib's
#             gpu:: tests) and _tailor.abi3.so (the module, built with the gpu feature);
#   .gl/      the Vulkan and GL loader packages (libvulkan1 ...), unpacked into / first.
# Writes everything into $OUT (or out/bench-gpu): the GPU's name and driver (machine.txt), the
# benchmark's tables (bench-gpu.md, solver.md with each kernel's profile), its log, the test
# suite's log and the samples' reports (reports.tgz): six files.
# Order: the GPU test suite first (a few seconds on hardware, and what says the port is right),
# then the figures, each step under its own timeout, so a slow step costs its own output and
# not the rest.
set -u
out=${OUT:-out/bench-gpu}
mkdir -p "$out"
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -e "$icd" ] && export VK_DRIVER_FILES=$icd
egl=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -e "$egl" ] && export __EGL_VENDOR_LIBRARY_FILENAMES=$egl
{
    nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv
    ldd --version | head -1
    nproc
    python3 --version
} >"$out/machine.txt" 2>&1
cat "$out/machine.txt"
{
    TAILOR_REQUIRE_GPU=1 timeout 120 .devbin/gpu_solver --test-threads 4
    echo "gpu_solver rc $?"
    TAILOR_REQUIRE_GPU=1 timeout 60 .devbin/core_lib gpu::
    echo "core_lib gpu:: rc $?"
} >"$out/tests.log" 2>&1
tail -5 "$out/tests.log"
cp .devbin/_tailor.abi3.so native/python/tailor/_tailor.abi3.so
export PYTHONPATH=$PWD/native/python PYTHONUNBUFFERED=1
python3 bench/gpu/run.py --out "$out" --bench-bin .devbin/gpu_bench --timeout "${BENCH_TIMEOUT:-150}" \
    --budget "${BENCH_BUDGET:-1.5}" --sizes ${BENCH_SIZES:-10000 30000 100000 1000000} \
    --frames "${BENCH_FRAMES:-90}" --samples "${BENCH_SAMPLES:-layered,tshirt,skirt,trousers}" \
    --two-level-samples "${BENCH_TWO_LEVEL_SAMPLES:-tshirt,skirt}" \
    2>&1 | tee "$out/bench.log"
# The device tool brings back at most 8 files: the samples' reports travel as one archive.
(cd "$out" && ls ./*.json >/dev/null 2>&1 && tar czf reports.tgz ./*.json && rm -f ./*.json)
ls "$out"
