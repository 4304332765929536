#!/usr/bin/env bash
# Installs the Debian packages softmc needs to build and test; idempotent, quiet when all is present.
set -euo pipefail

pkgs=(
  build-essential cmake ninja-build ccache pkg-config git
  clang libclang-rt-14-dev
  libtomlplusplus-dev libcli11-dev libfmt-dev libspdlog-dev nlohmann-json3-dev
  libcairo2-dev libsqlite3-dev libmodbus-dev libboost-dev libeigen3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-numpy
)

missing=()
for p in "${pkgs[@]}"; do
  # dpkg-query prints "install ok installed" only for packages that are fully installed.
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

[ ${#missing[@]} -eq 0 ] && exit 0

if [ "$(id -u)" -ne 0 ]; then
  echo "bootstrap: missing packages: ${missing[*]}" >&2
  echo "bootstrap: run as root (or install them with apt-get) and try again" >&2
  exit 1
fi

echo "bootstrap: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
