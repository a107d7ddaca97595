#!/usr/bin/env bash
# `make device-bin`: what `bench/gpu/on_device.sh` needs on a lent GPU machine that has no Rust
# toolchain and no network (docs/gpu.md, issue 27), built here into two git-ignored folders:
#   .devbin/  stripped release binaries: gpu_bench, the GPU test suites (gpu_solver, core_lib)
#             and the module (_tailor.abi3.so, with the gpu feature);
#   .gl/      the Vulkan and GL loader packages, for machines whose image has none.
# Then: the device tool's `run` with carry [".gl", ".devbin"] and the command
# `bash bench/gpu/on_device.sh` (its timeout: the bench's, about 6 minutes, plus the start).
set -euo pipefail
cd "$(dirname "$0")/../.."
exclude=$(git rev-parse --git-path info/exclude)
mkdir -p "$(dirname "$exclude")"
grep -qx '/.devbin/' "$exclude" 2>/dev/null || printf '/.devbin/\n/.gl/\n' >>"$exclude"
mkdir -p .devbin .gl
exe() {  # the executable cargo reports for a build of "$@"
    cargo "$@" --message-format=json 2>/dev/null | python3 -c '
import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable"):
        path = m["executable"]
print(path)'
}
strip -o .devbin/gpu_bench "$(exe build --release -p tailor-core --features gpu --example gpu_bench)"
strip -o .devbin/gpu_solver "$(exe test --no-run --release -p tailor-core --features gpu --test gpu_solver)"
strip -o .devbin/core_lib "$(exe test --no-run --release -p tailor-core --features gpu --lib)"
cargo build --release -p tailor-py --features gpu
strip -o .devbin/_tailor.abi3.so target/release/lib_tailor.so
o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
mkdir -p /tmp/amd64/partial
# shellcheck disable=SC2086
apt-get $o update >/dev/null && (cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
du -sh .devbin .gl
