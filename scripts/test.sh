#!/usr/bin/env bash
# Runs everything CI checks: installs lavapipe (Mesa's CPU Vulkan driver) and llvmpipe's GL (EGL)
# when missing and Xvfb when it is missing (as root), then formatting, clippy with warnings
# denied, every test, and the GPU tests again on GL.
set -euo pipefail
cd "$(dirname "$0")/.."

has_vulkan_driver() {
    compgen -G "/usr/share/vulkan/icd.d/*.json" >/dev/null || compgen -G "/etc/vulkan/icd.d/*.json" >/dev/null
}

has_library() {
    ldconfig -p | grep -q "$1"
}

# What the tests need from the system: a Vulkan driver and Mesa's GL (EGL and llvmpipe) for the
# GPU tests; Xvfb (an X server without a screen) and the X11 client libraries winit loads at
# run time for the viewer's tests.
missing=()
has_vulkan_driver || missing+=(mesa-vulkan-drivers)
command -v Xvfb >/dev/null || missing+=(xvfb)
has_library libEGL.so.1 || missing+=(libegl1)
has_library libEGL_mesa.so.0 || missing+=(libegl-mesa0)
compgen -G "/usr/lib/*/dri/swrast_dri.so" >/dev/null || missing+=(libgl1-mesa-dri)
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
        echo "warning: not root, cannot install ${missing[*]}: the GPU tests need a Vulkan driver (mesa-vulkan-drivers) and GL (libegl-mesa0, libgl1-mesa-dri), the viewer tests Xvfb (xvfb)" >&2
    fi
fi

cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
cargo test --workspace

# The GPU tests once more on llvmpipe's GL, the backend a machine without a Vulkan driver falls
# back to: every chiaro_gpu test (image against the CPU reference mode by mode, and the WGSL
# library against chiaro_shading), and the command line's and the embedding's renders. One is
# left on Vulkan: lights_parity's bound of 2e-5 on the solid angle of tiny triangles, which GL's
# fused multiply-adds move by up to 2e-4 (the images agree).
export WGPU_BACKEND=gl
cargo test -p chiaro_gpu --tests -- --skip wgsl_lights_match_chiaro_shading
cargo test -p chiaro --test cli_render --test embed_in_ecs --test walkthrough
