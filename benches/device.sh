#!/usr/bin/env bash
# The GPU checks for a machine with a real GPU and little time, prepared to fit its minutes.
#
#   bash benches/device.sh stage   # here, on the developer's machine (no GPU needed)
#   bash benches/device.sh run     # there, with what `stage` built carried over
#
# `stage` builds the bench and GPU test executables, strips them into target/device/ and packs
# that into target/device.txz (xz: the executables alone are over the 64 MiB a device call
# carries), and downloads the Vulkan and GL loaders into .gl/ (all ignored by git; carry .gl
# and target/device.txz), so the GPU machine compiles nothing. `run` unpacks both, then, on the
# real GPU and against its driver:
#   1. the tests that hold GPU output to the CPU's (every technique's agreement on every
#      catalogue scene, the rasterizer, the feature transform, device timing, own-device use)
#      and the stability suite (every technique on every catalogue scene, both backends);
#   2. the generation benches at 2048², GPU wall and device time, every configuration;
#   3. the evaluation benches (512² receivers, 1024² maps), GPU wall and device time;
#   4. the GPU frame's two ways to make its lamps' maps, `run` and `run_into`
#      (`frame/gpu-recording`, 1, 4 and 16 lamps);
# each of 2 and 3 measured for SHADOW_BENCH_SECONDS (default 0.5) instead of the usual 2 s, and
# writes into $OUT: gpu.txt, tests.txt, generation.txt, evaluation.txt, lights.txt and summary.md (every
# median, and the goals: 2048² generation under 1 ms, 1080p evaluation under 0.5 ms).
# GEN_FILTER and EVAL_FILTER (criterion regexes) narrow the benches, e.g. to rehearse `run`
# here on lavapipe.
set -uo pipefail
cd "$(dirname "$0")/.."
dir=target/device

stage() {
    set -e
    mkdir -p "$dir" .gl
    if ! ls .gl/libvulkan1_*.deb >/dev/null 2>&1; then
        # The device machine may lack the loaders; Debian's packages, unpacked there.
        local lists=/tmp/device-apt-lists
        mkdir -p "$lists/partial"
        local o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 "-oDir::State::Lists=$lists")
        apt-get "${o[@]}" update >/dev/null
        (cd .gl && apt-get "${o[@]}" download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 \
            libglx0 libgles2)
    fi
    # The executables cargo reports for each build, copied under their target's name: the
    # benches, and the test binaries with GPU tests (built as the README's test command
    # builds them, so its artifacts serve).
    executables() {
        cargo "$@" --message-format=json | python3 -c '
import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("executable"):
        print(m["target"]["name"], m["executable"])'
    }
    rm -f "$dir"/*
    local name path
    while read -r name path; do
        case $name in
        # Stripped: what travels to the device is at most 64 MiB, the tree included.
        generation | evaluation | lights | suite | stability | penumbra_limit | occlusion_slices) cp "$path" "$dir/$name" && strip "$dir/$name" ;;
        esac
    done < <(
        executables bench -p shadow-benches --no-run
        executables test --workspace --release --no-run
    )
    for name in generation evaluation lights suite stability penumbra_limit occlusion_slices; do
        [ -x "$dir/$name" ] || { echo "stage: no $name executable was built" >&2; exit 1; }
    done
    tar cJf "$dir.txz" -C "$(dirname "$dir")" "$(basename "$dir")"
    ls -l "$dir" "$dir.txz"
    cat <<'EOF'

Staged. On the GPU machine, from the repository root with .gl/ and target/device.txz carried
over (OUT names the folder it writes):
  OUT=/tmp/out bash benches/device.sh run     # about 2 minutes on an NVIDIA H200
summary.md holds every median.
EOF
}

# Each criterion bench's name and median ("name<TAB>value unit"), from its printed report; for
# a throughput line, the median throughput after the time.
medians() {
    awk '
        function flush() { if (rec != "") print rec; rec = "" }
        /^(generate|evaluate|write-once|frame)\// { flush(); name = $1 }
        # The first time and throughput after a name: a "change:" block repeats both in %.
        /time:/ && name != "" && rec == "" {
            s = $0; sub(/.*\[/, "", s); split(s, v, " "); rec = name "\t" v[3] " " v[4]
        }
        /thrpt:/ && rec != "" && split(rec, f, "\t") == 2 {
            s = $0; sub(/.*\[/, "", s); split(s, v, " "); rec = rec "\t" v[3] " " v[4]
        }
        END { flush() }
    ' "$1"
}

# Milliseconds of "value unit".
to_ms() {
    awk -v v="$1" -v u="$2" 'BEGIN {
        f = (u == "s") ? 1e3 : (u == "ms") ? 1 : (u == "µs" || u == "us") ? 1e-3 : (u == "ns") ? 1e-6 : -1
        printf "%.4g", v * f
    }'
}

summary() {
    local out=$1
    [ -f "$out/generation.txt" ] && [ -f "$out/evaluation.txt" ] || {
        echo "summary: $out holds no generation.txt and evaluation.txt from a run" >&2
        return 1
    }
    {
        echo "# $(grep -m 1 '^GPU benches' "$out/generation.txt")"
        echo
        echo "\`nvidia-smi -L\`: $(head -n 1 "$out/gpu.txt")"
        echo
        echo "Tests: $(grep -E '^test result' "$out/tests.txt" | tr '\n' ' ')"
        echo
        echo "## Generation (goal at 2048²: device time under 1 ms)"
        echo
        echo "| scene, configuration, map side | gpu-wall ms | gpu-device ms | under 1 ms |"
        echo "|---|---:|---:|---|"
        medians "$out/generation.txt" | awk -F'\t' '{ split($1, p, "/"); print p[2] "," p[3] "," p[5] "\t" p[4] "\t" $2 }' |
            while IFS=$'\t' read -r cfg backend time; do
                echo "$cfg $backend $(to_ms ${time% *} ${time#* })"
            done | awk '
                { ms[$1, $2] = $3; if (!($1 in seen)) { seen[$1] = 1; order[n++] = $1 } }
                END {
                    for (i = 0; i < n; i++) {
                        c = order[i]; d = ms[c, "gpu-device"]
                        ok = (d == "") ? "" : (d < 1.0 ? "yes" : "no")
                        printf "| %s | %s | %s | %s |\n", c, ms[c, "gpu-wall"], d, ok
                    }
                }'
        echo
        echo "## Evaluation, 512² receivers from 1024² maps (goal: 1080p, 2,073,600 receivers, under 0.5 ms of device time)"
        echo
        echo "| configuration | backend | ms per M receivers | ms at 1080p | under 0.5 ms |"
        echo "|---|---|---:|---:|---|"
        medians "$out/evaluation.txt" | while IFS=$'\t' read -r name time thrpt; do
            local cfg=${name#evaluate/*/} backend
            backend=${cfg##*/}
            cfg=${cfg%/*}
            # Throughput in elements per second: ms per million receivers is 1e9 / it.
            awk -v c="$cfg" -v b="$backend" -v v="${thrpt% *}" -v u="${thrpt#* }" 'BEGIN {
                f = (u == "Gelem/s") ? 1e9 : (u == "Melem/s") ? 1e6 : (u == "Kelem/s") ? 1e3 : 1
                per_m = 1e9 / (v * f); hd = per_m * 2.0736
                ok = (b == "gpu-device") ? (hd < 0.5 ? "yes" : "no") : ""
                printf "| %s | %s | %.4g | %.4g | %s |\n", c, b, per_m, hd, ok
            }'
        done
    } >"$out/summary.md"
}

run() {
    local out=${OUT:?run writes into the folder OUT names}
    if [ -f "$dir.txz" ]; then
        mkdir -p "$(dirname "$dir")" && tar xJf "$dir.txz" -C "$(dirname "$dir")"
    fi
    # The loaders, where the machine lacks them (unpacked over / as the device notes say).
    if ! ldconfig -p | grep -q 'libvulkan\.so\.1'; then
        for f in .gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
    fi
    local icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
    if [ -f "$icd" ]; then
        export VK_DRIVER_FILES=$icd
        export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
    fi
    export WGPU_BACKEND=${WGPU_BACKEND:-vulkan} CI=true
    export SHADOW_BENCH_SECONDS=${SHADOW_BENCH_SECONDS:-0.5}
    { nvidia-smi -L 2>/dev/null || echo "no nvidia-smi"; } >"$out/gpu.txt"
    # Failing tests do not stop the benches: each step's status goes to its file.
    {
        timeout 120 "$dir/suite" agree gpu_ device recycled --test-threads 4
        echo "exit status $?"
        timeout 60 "$dir/penumbra_limit" gpu_ --test-threads 4
        echo "exit status $?"
        timeout 60 "$dir/occlusion_slices" gpu_ --test-threads 4
        echo "exit status $?"
        timeout 120 "$dir/stability" catalogue --test-threads 8
        echo "exit status $?"
    } >"$out/tests.txt" 2>&1
    timeout 170 "$dir/generation" --noplot --bench "${GEN_FILTER:-/gpu-(device|wall)/2048\$}" \
        >"$out/generation.txt" 2>&1
    echo "exit status $?" >>"$out/generation.txt"
    timeout 170 "$dir/evaluation" --noplot --bench "${EVAL_FILTER:-/gpu-(device|wall)\$}" \
        >"$out/evaluation.txt" 2>&1
    echo "exit status $?" >>"$out/evaluation.txt"
    timeout 60 "$dir/lights" --noplot --bench gpu-recording >"$out/lights.txt" 2>&1
    echo "exit status $?" >>"$out/lights.txt"
    summary "$out"
    cat "$out/summary.md"
}

case "${1:-}" in
stage) stage ;;
run) run ;;
summary) summary "${2:?summary DIR: the folder run wrote}" && cat "$2/summary.md" ;;
*)
    echo "usage: bash benches/device.sh stage|run|summary DIR" >&2
    exit 2
    ;;
esac
