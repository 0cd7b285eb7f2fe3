#!/usr/bin/env bash
# Install MANTA's build and test dependencies from Debian packages.
# Idempotent: packages already present are skipped, and `apt-get update` runs at most once,
# only when something is missing. No downloads from anywhere but the Debian archive.
set -euo pipefail

packages=(
    build-essential cmake pkg-config
    libeigen3-dev        # linear algebra, AutoDiffScalar
    libyaml-cpp-dev      # configuration files
    libcli11-dev         # command line
    libspdlog-dev libfmt-dev
    libboost-dev         # Boost.Odeint (adaptive integration), Boost.Graph (node renumbering)
    libgtest-dev libgmock-dev
    libbenchmark-dev
    nlohmann-json3-dev   # JSON output (--json) and JSON files; see docs/adr/0002-json-library.md
    libnlopt-cxx-dev     # Kriging likelihood optimisation (surrogate)
    libsqlite3-dev       # sample store of table campaigns (tables)
    coinor-libipopt-dev  # interior-point NLP solver of the optimal-control transcription (optimal)
    chromium             # headless browser test of the HTML report (report)
    zlib1g-dev           # gzip-compressed SU2 meshes (mesh)
    libcgns-dev          # CGNS mesh reader (mesh)
    libgmsh-dev          # test meshes generated with the gmsh API (tests/mesh, tests/euler)
    libmetis-dev         # mesh partitioning (parallel)
    libopenmpi-dev openmpi-bin   # MPI processes of the Euler solver (parallel)
    clang-14 libclang-rt-14-dev  # libFuzzer targets of the mesh readers (make validate, fuzz/)
)

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
        missing+=("$p")
    fi
done

if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#packages[@]} packages present"
    exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
