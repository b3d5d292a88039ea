#!/usr/bin/env bash
# Runs the demo in a real window under Xvfb with Mesa's software Vulkan (lavapipe), visits
# every scene, saves one screenshot per scene to docs/screenshots/, and fails if the app
# panics or a screenshot is missing or blank.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-docs/screenshots}"

need=()
command -v xvfb-run >/dev/null || need+=(xvfb xauth)
[ -e /usr/share/vulkan/icd.d/lvp_icd.x86_64.json ] || ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1 || need+=(mesa-vulkan-drivers)
ldconfig -p | grep -q libvulkan.so.1 || need+=(libvulkan1)
convert -version 2>/dev/null | grep -q ImageMagick || need+=(imagemagick)
if [ ${#need[@]} -gt 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}"
fi

cargo build --release --features viz --example demo
rm -rf "$out" && mkdir -p "$out"
TUMBLE_TOUR="$out" WGPU_BACKEND=vulkan timeout 1800 \
  xvfb-run -a -s "-screen 0 1280x720x24" "${CARGO_TARGET_DIR:-target}/release/examples/demo" \
  || { echo "demo failed (exit $?)"; exit 1; }

status=0
for scene in assets/scenes/*.scene.ron; do
  name=$(basename "$scene" .scene.ron)
  png="$out/$name.png"
  if [ ! -s "$png" ]; then echo "missing screenshot: $png"; status=1; continue; fi
  # The 3D view right of the panel must not be one flat colour.
  spread=$(convert "$png" -crop 880x720+400+0 -colorspace Gray -format "%[fx:standard_deviation]" info:)
  if awk "BEGIN { exit !($spread < 0.02) }"; then echo "blank screenshot: $png (spread $spread)"; status=1; fi
  echo "ok $png (spread $spread)"
done
exit $status
