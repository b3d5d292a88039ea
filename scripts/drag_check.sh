#!/usr/bin/env bash
# Real-window check of the demo's keys and mouse drag (what the screenshot tour cannot
# reach): starts the demo under Xvfb with lavapipe, presses 2 (box tower), drags the top
# box sideways with xdotool, and saves before / during / after screenshots to look at.
# The tower is asleep when the drag starts, so this also shows a drag waking a sleeper.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-/tmp/drag_check}"

need=()
command -v Xvfb >/dev/null || need+=(xvfb)
command -v xdotool >/dev/null || need+=(xdotool)
ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1 || need+=(mesa-vulkan-drivers)
ldconfig -p | grep -q libvulkan.so.1 || need+=(libvulkan1)
command -v import >/dev/null || need+=(imagemagick)
if [ ${#need[@]} -gt 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}"
fi

cargo build --release --features viz --example demo
mkdir -p "$out"
display=:97
Xvfb "$display" -screen 0 1280x720x24 >/dev/null 2>&1 &
xvfb=$!
export DISPLAY=$display WGPU_BACKEND=vulkan
for _ in $(seq 60); do xdotool getdisplaygeometry >/dev/null 2>&1 && break; sleep 0.5; done
"${CARGO_TARGET_DIR:-target}/release/examples/demo" >"$out/demo.log" 2>&1 &
app=$!
trap 'kill $app $xvfb 2>/dev/null || true' EXIT

win=""
for _ in $(seq 120); do
  win=$(xdotool search --name '^tumble$' 2>/dev/null | head -1 || true)
  [ -n "$win" ] && break
  sleep 1
done
[ -n "$win" ] || { echo "no demo window"; exit 1; }
sleep 60 # shaders and the first frames under the software renderer
xdotool windowfocus --sync "$win" || true
xdotool key --window "$win" 2
sleep 30 # the tower settles and falls asleep
import -window root "$out/before.png"
# The top box of the tower is at about (640, 80) in the 1280×720 window.
# Frames are slow under the software renderer: hover first so picking sees the box, then
# press, then move in small steps so every step is a frame or more.
xdotool mousemove --sync 640 80
sleep 3
xdotool mousedown 1
sleep 2
for x in $(seq 660 20 900); do
  xdotool mousemove --sync "$x" 80
  sleep 0.5
done
sleep 8
import -window root "$out/during.png"
xdotool mouseup 1
sleep 15
import -window root "$out/after.png"
kill -0 "$app" || { echo "the demo exited"; tail -20 "$out/demo.log"; exit 1; }
echo "screenshots in $out: before.png during.png after.png"
