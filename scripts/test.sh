#!/usr/bin/env bash
# Runs everything CI checks: installs lavapipe (Mesa's CPU Vulkan driver) when no Vulkan driver
# is present and this runs as root, then formatting, clippy with warnings denied, and every test.
set -euo pipefail
cd "$(dirname "$0")/.."

has_vulkan_driver() {
    compgen -G "/usr/share/vulkan/icd.d/*.json" >/dev/null || compgen -G "/etc/vulkan/icd.d/*.json" >/dev/null
}

if ! has_vulkan_driver; then
    if [ "$(id -u)" = 0 ]; then
        echo "no Vulkan driver: installing lavapipe (mesa-vulkan-drivers)"
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq
        apt-get install -y -qq --no-install-recommends mesa-vulkan-drivers >/dev/null
    else
        echo "warning: no Vulkan driver and not root: install mesa-vulkan-drivers for the GPU tests" >&2
    fi
fi

cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
cargo test --workspace
