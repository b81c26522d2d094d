#!/usr/bin/env bash
# One-command setup on Debian (bookworm), as root: installs the Debian packages forestmod needs,
# fetches Debian's OpenCV source package of exactly the installed version (for opencv_ts, which
# Debian does not package), then configures and builds the library, tests, perf tests and samples.
# Idempotent: a second run installs nothing, downloads nothing and rebuilds only what changed.
#
#   scripts/setup.sh            # build into ./build
#   FORESTMOD_BUILD_DIR=/x scripts/setup.sh
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${FORESTMOD_BUILD_DIR:-$root/build}
jobs=${FORESTMOD_JOBS:-$(nproc)}
say() { printf '[setup] %s\n' "$*" >&2; }

# ---- 1. Debian packages ---------------------------------------------------------------------------
pkgs=(build-essential cmake ninja-build pkg-config dpkg-dev xz-utils ca-certificates
      libopencv-dev libopencv-contrib-dev libeigen3-dev libassimp-dev libosmesa6-dev python3)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  [ "$(id -u)" = 0 ] || { say "need root to install: ${missing[*]}"; exit 1; }
  say "installing ${missing[*]}"
  apt-get update -q
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  say "Debian packages: all present"
fi

# ---- 2. Debian's OpenCV source package, same version as the installed libopencv-dev ---------------
ocv_version=$(dpkg-query -W -f='${Version}' libopencv-dev)
ocv_source=$(dpkg-query -W -f='${source:Package}' libopencv-dev)
srcdir="$build/opencv-src"
stamp="$srcdir/.forestmod-source-version"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$ocv_source=$ocv_version" ]; then
  say "OpenCV source: $ocv_source=$ocv_version already in $srcdir"
else
  say "fetching Debian source package $ocv_source=$ocv_version"
  apt_dir="$build/apt"
  rm -rf "$apt_dir" "$srcdir"
  mkdir -p "$apt_dir/sources.list.d" "$apt_dir/lists/partial" "$apt_dir/cache/archives/partial" \
           "$apt_dir/download"
  # deb-src twins of the machine's own binary sources, kept inside the build folder:
  # /etc/apt is never touched.
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    grep -Eq '^Types:.*\bdeb\b' "$f" || continue
    sed -E 's/^Types:.*/Types: deb-src/' "$f" > "$apt_dir/sources.list.d/$(basename "$f")"
  done
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    sed -nE 's/^[[:space:]]*deb[[:space:]]+/deb-src /p' "$f" > "$apt_dir/sources.list.d/$(basename "$f").list"
  done
  apt_opts=(-q -o "Dir::Etc::SourceList=/dev/null" -o "Dir::Etc::SourceParts=$apt_dir/sources.list.d"
            -o "Dir::State::Lists=$apt_dir/lists" -o "Dir::Cache=$apt_dir/cache"
            -o "APT::Sandbox::User=root")
  apt-get "${apt_opts[@]}" update
  (cd "$apt_dir/download" && apt-get "${apt_opts[@]}" source --download-only "$ocv_source=$ocv_version")
  dsc=$(ls "$apt_dir"/download/*.dsc | head -n 1)
  dpkg-source --no-check -x "$dsc" "$srcdir" >/dev/null
  rm -rf "$apt_dir/download"          # the tarballs: 130 MB we no longer need
  [ -f "$srcdir/modules/ts/src/ts.cpp" ] || { say "no modules/ts in $srcdir"; exit 1; }
  echo "$ocv_source=$ocv_version" > "$stamp"
fi

# ---- 3. configure + build -------------------------------------------------------------------------
if [ ! -f "$build/CMakeCache.txt" ]; then
  say "configuring $build"
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DOPENCV_SOURCE_DIR="$srcdir"
fi
say "building with $jobs jobs"
cmake --build "$build" -j "$jobs"
say "done: $build"
