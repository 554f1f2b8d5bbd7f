#!/usr/bin/env bash
# A fuzzing campaign with libFuzzer over every target, one after the other.
#
#   fuzz/campaign.sh [SECONDS_PER_TARGET] [TARGET...]
#
# Default: 600 s for each of obj ply stl off gltf glb simplify (70 minutes, one
# core). Needs cargo-fuzz (`cargo install cargo-fuzz`); the stable
# toolchain serves with RUSTC_BOOTSTRAP=1 (cargo-fuzz passes nightly-only
# sanitizer flags). The seed corpus is generated in code first; libFuzzer
# grows it in fuzz/corpus/<target>. Crashes, timeouts and OOMs are kept in
# fuzz/artifacts/<target> and the run goes on (fork mode); logs and the
# final statistics go to fuzz/logs/<target>.log. Copy a finding into
# crates/fuzz/regressions/<target>/ once fixed: `cargo test` replays it.
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-600}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    targets=(obj ply stl off gltf glb simplify)
fi
export RUSTC_BOOTSTRAP=1
cargo run -q --release -p wildlod-fuzz --bin seed-corpus -- fuzz/corpus
cargo fuzz build -O
mkdir -p fuzz/logs
for t in "${targets[@]}"; do
    mkdir -p "fuzz/artifacts/$t"
    echo "== $t: ${secs}s"
    cargo fuzz run -O "$t" "fuzz/corpus/$t" -- \
        -max_total_time="$secs" -timeout=10 -rss_limit_mb=4096 -max_len=16384 \
        -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
        -print_final_stats=1 >"fuzz/logs/$t.log" 2>&1 || true
    tail -n 3 "fuzz/logs/$t.log"
    echo "findings: $(ls "fuzz/artifacts/$t" | wc -l)"
done
