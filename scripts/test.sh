#!/usr/bin/env bash
# Runs everything CI checks: installs lavapipe (Mesa's CPU Vulkan driver) when no Vulkan driver
# is present and Xvfb when it is missing (as root), then formatting, clippy with warnings denied,
# and every test.
set -euo pipefail
cd "$(dirname "$0")/.."

has_vulkan_driver() {
    compgen -G "/usr/share/vulkan/icd.d/*.json" >/dev/null || compgen -G "/etc/vulkan/icd.d/*.json" >/dev/null
}

has_library() {
    ldconfig -p | grep -q "$1"
}

# What the tests need from the system: a Vulkan driver for the GPU tests; Xvfb (an X server
# without a screen) and the X11 client libraries winit loads at run time for the viewer's tests.
missing=()
has_vulkan_driver || missing+=(mesa-vulkan-drivers)
command -v Xvfb >/dev/null || missing+=(xvfb)
has_library libX11-xcb.so.1 || missing+=(libx11-xcb1)
has_library libXcursor.so.1 || missing+=(libxcursor1)
has_library libXrandr.so.2 || missing+=(libxrandr2)
has_library libXi.so.6 || missing+=(libxi6)
has_library libxkbcommon-x11.so.0 || missing+=(libxkbcommon-x11-0)

if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" = 0 ]; then
        echo "installing ${missing[*]}"
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq
        apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
    else
        echo "warning: not root, cannot install ${missing[*]}: the GPU tests need a Vulkan driver (mesa-vulkan-drivers), the viewer tests Xvfb (xvfb)" >&2
    fi
fi

cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
cargo test --workspace
