#!/usr/bin/env bash
# Equal-time error of the CPU reference's integrators (pt, ptlt, bdpt, mlt, mmlt) against a long
# render, and each one's efficiency, 1 / (relMSE x seconds). For every scene: a reference
# (REF_INTEGRATOR, REF_SECONDS of paths at the throughput a short run measures), then each
# integrator at RUN_SECONDS of paths, scored with `chiaro compare`. Prints one markdown row per
# scene and integrator.
# Usage: bash scripts/integrator_efficiency.sh [SCENE...]
#   env: CHIARO (binary, default target/release/chiaro), SIZE (64x64), RUN_SECONDS (8),
#        REF_SECONDS (150), REF_INTEGRATOR (bdpt), OUT (integrator-efficiency),
#        INTEGRATORS (pt ptlt bdpt mlt mmlt)
set -euo pipefail
cd "$(dirname "$0")/.."
chiaro="${CHIARO:-target/release/chiaro}"
size="${SIZE:-64x64}"
seconds="${RUN_SECONDS:-8}"
ref_seconds="${REF_SECONDS:-150}"
ref_integrator="${REF_INTEGRATOR:-bdpt}"
out="${OUT:-integrator-efficiency}"
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(builtin:door builtin:lamp builtin:caustic builtin:cornell
    builtin:hard-cases builtin:instances builtin:many-lights)
pixels=$(( ${size%x*} * ${size#*x} ))
mkdir -p "$out"

# Paths per second of integrator $2 on scene $1 (a short run).
throughput() {
    "$chiaro" reference "$1" --integrator "$2" --size "$size" --spp 8 --seed 3 \
        --out "$out/probe.exr" 2>&1 | awk '/^paths\/s:/ { print $2 }'
}

# Samples per pixel that take about $2 seconds at $1 paths/s (at least 2).
spp_for() {
    awk -v rate="$1" -v s="$2" -v px="$pixels" 'BEGIN { n = int(rate * s / px); print (n < 2 ? 2 : n) }'
}

echo "| scene | integrator | spp | seconds | relMSE | efficiency |"
echo "|---|---|---|---|---|---|"
for scene in "${scenes[@]}"; do
    name="${scene#builtin:}"
    ref="$out/$name-reference.exr"
    if [ ! -f "$ref" ]; then
        spp=$(spp_for "$(throughput "$scene" "$ref_integrator")" "$ref_seconds")
        "$chiaro" reference "$scene" --integrator "$ref_integrator" --size "$size" --spp "$spp" --seed 7 \
            --out "$ref" > "$out/$name-reference.log" 2>&1
    fi
    noise=$(awk '/relMSE between independent halves/ { print $5 }' "$out/$name-reference.log")
    ref_spp=$(awk '/ spp in / { print $3 }' "$out/$name-reference.log")
    echo "| $scene | reference: $ref_integrator, $ref_spp spp, halves' relMSE $noise | | | | |"
    for integrator in ${INTEGRATORS:-pt ptlt bdpt mlt mmlt}; do
        rate=$(throughput "$scene" "$integrator")
        spp=$(spp_for "$rate" "$seconds")
        image="$out/$name-$integrator.exr"
        log=$("$chiaro" reference "$scene" --integrator "$integrator" --size "$size" \
            --spp "$spp" --seed 11 --out "$image" 2>&1)
        elapsed=$(echo "$log" | awk '/ spp in / { print $(NF-1) }')
        relmse=$("$chiaro" compare "$image" "$ref" | awk '/^relmse/ { print $2 }')
        efficiency=$(awk -v e="$relmse" -v t="$elapsed" 'BEGIN { printf "%.3g", 1 / (e * t) }')
        echo "| $scene | $integrator | $spp | $elapsed | $relmse | $efficiency |"
    done
done
