#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine:
#   scripts/setup.sh run    install what is missing, build, run the main example (the collapsing rings)
#   scripts/setup.sh test   install what is missing, build, run the test suite (ctest)
#   scripts/setup.sh build  install and build only
# Idempotent: packages already present are not reinstalled, the build is incremental.
# (xvfb and xauth: postprocess/ renders VTK pictures offscreen under xvfb-run, which needs xauth,
# only recommended by xvfb and so not installed by --no-install-recommends. libopenblas0-pthread:
# an optimized BLAS/LAPACK; installing it points Debian's libblas.so.3/liblapack.so.3 alternatives
# at OpenBLAS instead of the reference BLAS, which SuperLU, Ifpack2 and the SPAI's dense least
# squares otherwise run on.)
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-build}"

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libdeal.ii-dev trilinos-all-dev libopenmpi-dev openmpi-bin libmetis-dev
  libsuperlu-dev libsuperlu-dist-dev libopenblas0-pthread gmsh libgmsh-dev
  libgtest-dev python3-numpy python3-scipy python3-matplotlib python3-vtk9 xvfb xauth python3-petsc4py
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Open MPI refuses to run as root unless told (containers, CI).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
# One BLAS thread per process: the apps run one MPI rank per core, and OpenBLAS' own threads
# would oversubscribe the cores (set it to more for a serial run with spare cores).
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}"

jobs="$(nproc)"
# Warnings are errors here (CI): the project's own code builds warning-free with -Wall -Wextra.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSADDLE_POINT_WERROR=ON >/dev/null
cmake --build build -j "$jobs"

case "$mode" in
  run)
    # The main example: the collapsing rings (apps/contact_rings_2d.prm, 24 rings with Coulomb
    # friction pressed by a plate until the pile collapses), 2 ranks; output in
    # output/contact_rings_2d (ParaView: solution.pvd; postprocess/render_all.py draws it).
    mpirun -np 2 build/apps/contact_blocks apps/contact_rings_2d.prm
    ;;
  test)
    cd build && ctest --output-on-failure -j "$jobs" -LE benchmark
    ;;
  build) ;;
  *) echo "setup: unknown mode '$mode' (expected run, test or build)" >&2; exit 2 ;;
esac
