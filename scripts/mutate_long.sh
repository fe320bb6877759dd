#!/usr/bin/env bash
# A long mutation run of the glTF importer: N mutants of every shared sample model (default
# 2000 each, 10,000 in all: a few minutes on 2 cores), in the test build. Each must load or be
# refused with an error naming the file, without a panic, a hang or an allocation beyond the
# test's bound; the summary line gives the counts by outcome.
# Usage: bash scripts/mutate_long.sh [N]
set -euo pipefail
cd "$(dirname "$0")/.."
CHIARO_MUTANTS="${1:-2000}" cargo test --test mutated_gltf -- --nocapture
