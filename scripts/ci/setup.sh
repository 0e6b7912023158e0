#!/usr/bin/env bash
# Installs the Debian packages the solver needs. Idempotent: packages already present are skipped,
# and apt-get is not called at all when nothing is missing. Run as root on Debian 12.
set -euo pipefail

packages=(
  build-essential cmake git pkg-config
  clang-format             # scripts/ci/check_format.sh (CI)
  libeigen3-dev            # dense small matrices in tests and the CPU sparse solvers
  libtoml11-dev            # case files
  libcli11-dev             # command line
  libgtest-dev libgmock-dev googletest
  libhdf5-dev              # snapshots (optional at configure time)
  libhypre-dev libopenmpi-dev openmpi-bin   # BoomerAMG (optional at configure time)
  libcgal-dev              # bodies from STL meshes (optional at configure time)
  python3-matplotlib python3-numpy python3-h5py   # plotting scripts, run with /usr/bin/python3
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "setup: installing ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "setup: missing packages and not root; run as root or install them: ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${missing[@]}"
